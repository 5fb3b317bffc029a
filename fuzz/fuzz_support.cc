#include "fuzz_support.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdlib>
#include <optional>

#include "gyrocomp/io/bag.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/gyro_log.h"
#include "gyrocomp/io/io.h"

namespace gyrocomp::fuzz {

MemoryFile::MemoryFile(const std::uint8_t* data, std::size_t size) {
  fd_ = ::memfd_create("gyrocomp_fuzz", MFD_CLOEXEC);
  if (fd_ < 0) std::abort();
  std::size_t done = 0;
  while (done < size) {
    const ssize_t w = ::write(fd_, data + done, size - done);
    if (w <= 0) std::abort();
    done += static_cast<std::size_t>(w);
  }
  path_ = "/proc/self/fd/" + std::to_string(fd_);
}

MemoryFile::~MemoryFile() { ::close(fd_); }

void ReadAndLoad(const std::string& path) {
  CsvReadOptions read;
  read.max_memory_bytes = std::size_t{4} << 20;  // stay well inside libFuzzer's -rss_limit_mb
  Result<Table> table = ReadCsv(path, read);
  if (!table) return;
  LogSpec spec;
  spec.temp_required = false;
  spec.max_memory_bytes = std::size_t{4} << 20;
  (void)LoadGyroLog(*table, spec);
  spec.fs_hz = 100.0;
  (void)LoadGyroLog(*table, spec);
  spec.fs_hz.reset();
  spec.resample_hz = 50.0;
  Result<GyroLog> resampled = LoadGyroLog(*table, spec);
  if (resampled) (void)ResampleTable(*table, spec.time_col, 50.0);
  if (table->names.size() >= 2) {
    LogSpec axes;
    axes.time_col = table->names[0];
    axes.rate_cols = {table->names[1]};
    if (table->names.size() >= 3) axes.temp_col = table->names[2];
    axes.max_memory_bytes = std::size_t{4} << 20;
    (void)LoadGyroLog(*table, axes);
  }
}

void ReadFlightLog(const std::string& path) {
  for (const std::optional<int> instance : {std::optional<int>(), std::optional<int>(0), std::optional<int>(1)}) {
    LogSpec spec;
    spec.instance = instance;
    spec.max_memory_bytes = std::size_t{4} << 20;
    Result<LogTableRead> read = ReadLogTable(path, spec);
    if (read) (void)LoadGyroLog(read->table, read->spec);
  }
}

void ReadBag(const std::string& path) {
  BagReadOptions options;
  options.max_chunk_bytes = std::uint64_t{16} << 20;
  options.max_decompressed_file_bytes = std::uint64_t{16} << 20;  // .zstd files: a bomb stops at 16 MiB
  (void)ListBag(path, options);
  (void)ReadBagImu(path, options);
  options.time = BagTimeSource::kReceive;
  options.topic = "/imu0";
  (void)ReadBagImu(path, options);
  ReadFlightLog(path);
}

}  // namespace gyrocomp::fuzz
