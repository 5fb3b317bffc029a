// libFuzzer harness: the PX4 ULog reader on arbitrary bytes: ParseULog directly, then what every
// -i command does with such a file (ReadLogTable: format by the first bytes, instance choice,
// gyro table; LoadGyroLog on it).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "gyrocomp/io/flight_log.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  (void)gyrocomp::ParseULog(data, size, "fuzz");
  gyrocomp::fuzz::MemoryFile file(data, size);
  gyrocomp::fuzz::ReadFlightLog(file.path());
  return 0;
}
