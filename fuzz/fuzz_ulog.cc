// libFuzzer harness: the PX4 ULog reader on arbitrary bytes: the parser directly, then what every -i
// command does with such a file (ReadLogTable: format by the first bytes, instance choice, gyro
// table; LoadGyroLog on it). Record-level mutations of known logs check that recovery never
// invents a row (fuzz_records.h).
#include <cstddef>
#include <cstdint>

#include "fuzz_records.h"

GYROCOMP_RECORD_FUZZER(kULog)
