// libFuzzer harness: the CSV reader and the log loader on arbitrary bytes (plain text, or gzip
// when the bytes start with the gzip magic: ReadCsv detects it by content).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  gyrocomp::fuzz::MemoryFile file(data, size);
  gyrocomp::fuzz::ReadAndLoad(file.path());
  return 0;
}
