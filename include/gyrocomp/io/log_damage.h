// Damage found in a binary flight log and skipped by a reader that resynchronised after it.
//
// A reader in recovery mode (the default; `strict` in its options refuses instead) keeps every
// record it can validate and skips the bytes between a damaged record and the next record that
// passes the format's own checks (ULog: message size and type, subscription and data size, sync
// magic; DataFlash: A3 95, a type some FMT defined, that type's length, and a valid header right
// after it). Rows are never invented or altered: each kept row is the bytes of one intact record.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace gyrocomp {

// One skipped byte range [begin, end) of the file.
struct LogDamage {
  // An empty range.
  LogDamage() = default;
  // The bytes [begin_byte, end_byte) skipped, and why; no rows counted yet.
  LogDamage(std::size_t begin_byte, std::size_t end_byte, std::string why)
      : begin(begin_byte), end(end_byte), what(std::move(why)) {}
  std::size_t begin = 0;  // byte offset of the first skipped byte
  std::size_t end = 0;  // byte offset just past the last skipped byte
  std::string what;  // why the record at `begin` was refused
  // Rows lost, per topic and instance ("sensor_gyro 0", "IMU 1"), for the records in the range
  // whose topic could still be told (a record header intact, or a data size only one topic has).
  std::map<std::string, std::size_t> rows_lost;
  std::size_t records_unidentified = 0;  // records (or parts) in the range no topic could be given to
};

// One line for a file's damage ("<source>: damaged: 2 byte ranges skipped (...)"), empty when none.
std::string DamageWarning(const std::string& source, const std::vector<LogDamage>& damage);

// The damage as JSON: [{"begin_byte", "end_byte", "bytes", "what", "rows_lost": {...},
// "records_unidentified"}].
nlohmann::json DamageJson(const std::vector<LogDamage>& damage);

}  // namespace gyrocomp
