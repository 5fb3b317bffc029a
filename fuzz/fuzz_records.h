// Structure-aware fuzzing of the ULog and DataFlash readers: a libFuzzer custom mutator that
// works on whole records, and the invariant of recovery checked against the seed a mutated input
// came from.
//
// Inputs come in two kinds.
// - A tagged input, kTag + uint8 seed id + log bytes, derives from a known original log (the
//   simulated one each harness builds, id 0, and the files of $GYROCOMP_FUZZ_ORIGINALS in name
//   order, ids 1, 2, ...). The mutator changes it only by whole records, cut and joined where a
//   record of the original still intact begins or ends (never inside damaged bytes): delete, duplicate, swap
//   two neighbours ("flip"), truncate inside a record, damage a record's header so that it must
//   be refused (ULog: a msg_id nobody subscribed; DataFlash: a broken A3 95 or a type no FMT
//   defined), and splices of two tagged inputs of the same seed. The harness then checks that the
//   reader (recovery on) accepts the log and that every row it reads is a row of the original,
//   bit for bit; a violation aborts (a crash for libFuzzer).
// - Any other input is mutated byte by byte (LLVMFuzzerMutate) and only has to not crash; now and
//   then the mutator replaces it with a tagged original, so the tagged kind is always explored.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace gyrocomp::fuzz {

inline constexpr char kTag[] = "GCSEED";  // 6 bytes, then the seed id
inline constexpr std::size_t kTagBytes = 7;

enum class LogKind { kULog, kDataFlash };

// Loads the originals (built-in simulated log + $GYROCOMP_FUZZ_ORIGINALS) once.
void InitOriginals(LogKind kind);

// The harness body: reads `data` (tagged or not) with every reader path and, when tagged, checks
// the invariant above (std::abort with a message on stderr when it breaks).
void RunRecordHarness(LogKind kind, const std::uint8_t* data, std::size_t size);

// The custom mutator and cross-over (see above).
std::size_t MutateRecords(LogKind kind, std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned seed);
std::size_t CrossOverRecords(LogKind kind, const std::uint8_t* a, std::size_t a_size, const std::uint8_t* b,
                             std::size_t b_size, std::uint8_t* out, std::size_t max_out, unsigned seed);

}  // namespace gyrocomp::fuzz

// The three libFuzzer entry points of a record-level harness (fuzz_ulog.cc, fuzz_dataflash.cc).
#define GYROCOMP_RECORD_FUZZER(KIND)                                                                          \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {                         \
    gyrocomp::fuzz::RunRecordHarness(gyrocomp::fuzz::LogKind::KIND, data, size);                               \
    return 0;                                                                                                  \
  }                                                                                                            \
  extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,   \
                                                 unsigned int seed) {                                          \
    return gyrocomp::fuzz::MutateRecords(gyrocomp::fuzz::LogKind::KIND, data, size, max_size, seed);           \
  }                                                                                                            \
  extern "C" std::size_t LLVMFuzzerCustomCrossOver(const std::uint8_t* a, std::size_t a_size,                  \
                                                   const std::uint8_t* b, std::size_t b_size, std::uint8_t* out, \
                                                   std::size_t max_out, unsigned int seed) {                   \
    return gyrocomp::fuzz::CrossOverRecords(gyrocomp::fuzz::LogKind::KIND, a, a_size, b, b_size, out, max_out, \
                                            seed);                                                             \
  }
