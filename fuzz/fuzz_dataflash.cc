// libFuzzer harness: the ArduPilot DataFlash reader on arbitrary bytes: ParseDataFlash directly, then what every
// -i command does with such a file (ReadLogTable: format by the first bytes, instance choice,
// gyro table; LoadGyroLog on it). Record-level mutations of known logs check that recovery never
// invents a row (fuzz_records.h).
#include <cstddef>
#include <cstdint>

#include "fuzz_records.h"

using gyrocomp::fuzz::LogKind;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  gyrocomp::fuzz::RunRecordHarness(LogKind::kDataFlash, data, size);
  return 0;
}

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  return gyrocomp::fuzz::MutateRecords(LogKind::kDataFlash, data, size, max_size, seed);
}

extern "C" std::size_t LLVMFuzzerCustomCrossOver(const std::uint8_t* a, std::size_t a_size, const std::uint8_t* b,
                                                 std::size_t b_size, std::uint8_t* out, std::size_t max_out,
                                                 unsigned int seed) {
  return gyrocomp::fuzz::CrossOverRecords(LogKind::kDataFlash, a, a_size, b, b_size, out, max_out, seed);
}
