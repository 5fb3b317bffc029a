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

// One skipped byte range [begin, end) of the file (or, for a rosbag2 .db3, a range of message ids).
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
  // true: [begin, end) are rosbag2 messages.id values, not bytes (a .db3 is read through SQLite,
  // which names rows, not offsets); end == begin when no row after the damage could be read.
  bool message_ids = false;
};

// One line for a file's damage ("<source>: damaged: skipped 2 byte ranges (...)"; a .db3's as
// message id ranges), empty when none.
std::string DamageWarning(const std::string& source, const std::vector<LogDamage>& damage);

// The damage as JSON: [{"begin_byte", "end_byte", "bytes", "what", "rows_lost": {...},
// "records_unidentified"}]; a message id range has "begin_message_id", "end_message_id" (null:
// nothing after it could be read) and "messages" (ids in the range) instead of the byte keys.
nlohmann::json DamageJson(const std::vector<LogDamage>& damage);

}  // namespace gyrocomp
