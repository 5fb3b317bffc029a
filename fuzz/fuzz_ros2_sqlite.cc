// libFuzzer harness: the rosbag2 sqlite3 reader (src/io/ros2_sqlite.cc) and the CDR decoder on
// arbitrary bytes. sqlite3 opens files by name and looks for "<name>-journal" / "-wal" beside
// them, so the bytes are written to a real temporary file (one per process, rewritten for each
// input, removed with its side files afterwards), then read as every -i command reads a .db3
// (fuzz::ReadBag): the topic listing, the IMU table by header stamp and by receive time,
// ReadLogTable + LoadGyroLog.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fuzz_support.h"

namespace {

const std::string& TempPath() {
  static const std::string path = [] {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir && *dir ? dir : "/tmp") + "/gyrocomp_fuzz_ros2_sqlite_" + std::to_string(::getpid()) + ".db3";
  }();
  return path;
}

void RemoveAll(const std::string& path) {
  for (const char* side : {"", "-journal", "-wal", "-shm"}) std::remove((path + side).c_str());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = TempPath();
  RemoveAll(path);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  if (std::fclose(f) != 0) std::abort();
  gyrocomp::fuzz::ReadBag(path);
  RemoveAll(path);
  return 0;
}
