// libFuzzer harness: the ArduPilot DataFlash reader on arbitrary bytes: ParseDataFlash directly, then what every
// -i command does with such a file (ReadLogTable: format by the first bytes, instance choice,
// gyro table; LoadGyroLog on it).
#include <cstddef>
#include <cstdint>
#include <optional>

#include "fuzz_support.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/gyro_log.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  (void)gyrocomp::ParseDataFlash(data, size, "fuzz");
  gyrocomp::fuzz::MemoryFile file(data, size);
  for (const std::optional<int> instance : {std::optional<int>(), std::optional<int>(0), std::optional<int>(1)}) {
    gyrocomp::LogSpec spec;
    spec.instance = instance;
    spec.max_memory_bytes = std::size_t{4} << 20;
    gyrocomp::Result<gyrocomp::LogTableRead> read = gyrocomp::ReadLogTable(file.path(), spec);
    if (read) (void)gyrocomp::LoadGyroLog(read->table, read->spec);
  }
  return 0;
}
