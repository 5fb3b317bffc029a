// Helpers shared by the harnesses.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace gyrocomp::fuzz {

// An in-memory file holding `data` (memfd), named "/proc/self/fd/N" for readers that take a
// path. Closed on destruction.
class MemoryFile {
 public:
  MemoryFile(const std::uint8_t* data, std::size_t size);
  ~MemoryFile();
  const std::string& path() const { return path_; }

 private:
  int fd_ = -1;
  std::string path_;
};

// Reads the file through ReadCsv and, when it parses, LoadGyroLog with a few specs (time
// column, --fs, --resample, several axes): what every subcommand does with -i.
void ReadAndLoad(const std::string& path);

// What every -i command does with a flight log at `path`: ReadLogTable (format by the first
// bytes, instance choice: none, 0, 1) and, when it reads, LoadGyroLog on the table.
void ReadFlightLog(const std::string& path);

// What every -i command does with a ROS bag at `path` (MCAP, ROS 1, rosbag2 sqlite3, or a whole
// zstd-compressed one), chunks and .zstd files bounded at 16 MiB: the topic listing (every record
// visited), the IMU table by header stamp and, for topic /imu0, by receive time; then
// ReadFlightLog (ReadLogTable + LoadGyroLog). Shared by fuzz_mcap, fuzz_rosbag1, fuzz_ros2_sqlite.
void ReadBag(const std::string& path);

}  // namespace gyrocomp::fuzz
