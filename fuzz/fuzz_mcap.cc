// libFuzzer harness: the MCAP reader (src/io/mcap.cc) and the CDR decoder on arbitrary bytes,
// through what every -i command does with such a file: the topic listing (every record
// visited), the IMU table (chunks decompressed with a 16 MiB bound, sensor_msgs/Imu and
// Temperature decoded, by header stamp and by receive time) and ReadLogTable + LoadGyroLog.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "gyrocomp/io/bag.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  gyrocomp::fuzz::MemoryFile file(data, size);
  gyrocomp::BagReadOptions options;
  options.max_chunk_bytes = std::uint64_t{16} << 20;
  options.max_decompressed_file_bytes = std::uint64_t{16} << 20;  // .zstd files: a bomb stops at 16 MiB
  (void)gyrocomp::ListBag(file.path(), options);
  (void)gyrocomp::ReadBagImu(file.path(), options);
  options.time = gyrocomp::BagTimeSource::kReceive;
  options.topic = "/imu0";
  (void)gyrocomp::ReadBagImu(file.path(), options);
  gyrocomp::fuzz::ReadFlightLog(file.path());
  return 0;
}
