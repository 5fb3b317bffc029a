// libFuzzer harness: the ROS 1 bag v2.0 reader (src/io/rosbag1.cc) and the ROS 1 message
// decoder on arbitrary bytes, through what every -i command does with such a file
// (fuzz::ReadBag): the topic listing, the IMU table by header stamp and by receive time,
// ReadLogTable + LoadGyroLog.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  gyrocomp::fuzz::MemoryFile file(data, size);
  gyrocomp::fuzz::ReadBag(file.path());
  return 0;
}
