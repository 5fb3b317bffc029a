// rosbag2 sqlite3 storage reader (include/gyrocomp/io/bag.h): ros2/rosbag2,
// rosbag2_storage_default_plugins / rosbag2_storage_sqlite3, sqlite_storage.cpp, which creates
//     CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
//                         serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL)
//     CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,
//                           timestamp INTEGER NOT NULL, data BLOB NOT NULL)
// (later versions add a 'schema' / 'metadata' table and more topic columns; only the columns
// above are read). messages.timestamp is the receive time in ns; data is the CDR message as
// the rmw serialized it (serialization_format "cdr"). Messages are visited in id (insertion)
// order, one row at a time (sqlite3_step), so only wanted rows' data are handed on. The reader's
// class is in ros2_sqlite_reader.h; reading on past a damaged page in ros2_sqlite_recovery.cc.
#include <limits>

#include "ros2_sqlite_reader.h"

namespace gyrocomp {

namespace ros2_sqlite_internal {

namespace {

std::string Text(sqlite3_stmt* s, int col) {
  const unsigned char* t = sqlite3_column_text(s, col);
  return t ? reinterpret_cast<const char*>(t) : "";
}

}  // namespace

// A damaged file (SQLITE_CORRUPT) says so; anything else, "file is not a database" included, may
// be a file that is no rosbag2 database at all.
Error Ros2SqliteReader::SqlError(const std::string& what) const {
  const bool corrupt = (sqlite3_errcode(db_.get()) & 0xff) == SQLITE_CORRUPT;
  return InvalidInput(path_ + ": " + what + ": " + sqlite3_errmsg(db_.get()) +
                      (corrupt ? " (a damaged sqlite3 file)" : " (not a rosbag2 sqlite3 file?)"));
}

std::optional<Error> Ros2SqliteReader::Run() {
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(path_.c_str(), &raw, SQLITE_OPEN_READONLY, ShortReadIsDamageVfs());
  db_.reset(raw);
  if (rc != SQLITE_OK) return IoError(path_ + ": cannot open as sqlite3: " + (raw ? sqlite3_errmsg(raw) : "out of memory"));
  // sqlite3 pragma.html "cell_size_check": more damage is found as pages are read (a cell whose
  // size runs off its page is then an error instead of bytes read from the next cell).
  sqlite3_exec(db_.get(), "PRAGMA cell_size_check = ON", nullptr, nullptr, nullptr);
  // A file shorter than its header's page count (cut by a copy that lost power) is refused whole
  // unless writable_schema is on (btree.c lockBtree); then SQLite reads the pages the file has
  // and reports the missing ones damaged. The connection is read-only: nothing is written.
  if (!options_.strict) sqlite3_exec(db_.get(), "PRAGMA writable_schema = ON", nullptr, nullptr, nullptr);
  if (auto e = ReadTopics()) return e;
  return ReadMessages();
}

// The topics table is not read past damage: without a message's topic its bytes cannot be
// decoded, and a .db3 keeps its few topics in one page.
std::optional<Error> Ros2SqliteReader::ReadTopics() {
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_.get(), "SELECT id, name, type, serialization_format FROM topics", -1, &st, nullptr) != SQLITE_OK) {
    return SqlError("reading table 'topics'");
  }
  Stmt topics(st, &sqlite3_finalize);
  int step = 0;
  while ((step = sqlite3_step(topics.get())) == SQLITE_ROW) {
    BagChannel ch;
    ch.id = static_cast<std::uint64_t>(sqlite3_column_int64(topics.get(), 0));
    ch.topic = Text(topics.get(), 1);
    ch.type = Text(topics.get(), 2);
    ch.encoding = Text(topics.get(), 3);
    topics_[ch.id] = {ch.topic, ch.type, ch.encoding};
    if (auto e = visitor_->OnChannel(ch)) return e;
  }
  if (step != SQLITE_DONE) return SqlError("reading table 'topics'");
  return std::nullopt;
}

// Every message's topic and time (for counts), its data only when wanted. A step that finds a
// damaged page is an error in strict mode; otherwise reading goes on at the next readable row.
std::optional<Error> Ros2SqliteReader::ReadMessages() {
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_.get(), "SELECT id, topic_id, timestamp, data FROM messages WHERE id >= ?1 ORDER BY id", -1,
                         &st, nullptr) != SQLITE_OK) {
    return SqlError("reading table 'messages'");
  }
  messages_.reset(st);
  std::optional<sqlite3_int64> last;  // the last row read
  int step = Seek(std::numeric_limits<sqlite3_int64>::min());
  while (step != SQLITE_DONE) {
    std::string why;
    if (step == SQLITE_ROW) {
      const sqlite3_int64 id = sqlite3_column_int64(messages_.get(), 0);
      if (!last || id > *last) {
        last = id;
        if (auto e = OnRow(id)) return e;
        step = sqlite3_step(messages_.get());
        continue;
      }
      // Ids come in order from an intact table: one out of order is a damaged page SQLite read.
      why = "message id " + std::to_string(id) + " out of order";
    } else if (IsDamage(step)) {
      why = sqlite3_errmsg(db_.get());
    } else {
      return SqlError("reading table 'messages'");
    }
    if (options_.strict) {
      return InvalidInput(path_ + ": table 'messages' " +
                          (last ? "after message id " + std::to_string(*last) : std::string("at its first row")) + ": " +
                          why + " (a damaged sqlite3 file)");
    }
    step = ReadOnAfter(last, why);
  }
  ReportDamage();
  return std::nullopt;
}

std::optional<Error> Ros2SqliteReader::OnRow(sqlite3_int64 id) {
  if (!options_.strict && SkipIncomplete(id)) return std::nullopt;
  const auto topic = static_cast<std::uint64_t>(sqlite3_column_int64(messages_.get(), 1));
  const sqlite3_int64 t = sqlite3_column_int64(messages_.get(), 2);
  BagPosition where;
  where.message_id = id;
  if (t < 0) return InvalidInput(path_ + ": " + where.ToString() + ": negative timestamp " + std::to_string(t));
  visitor_->Count(topic, static_cast<std::uint64_t>(t));
  if (!visitor_->Wants(topic)) return std::nullopt;
  const void* blob = sqlite3_column_blob(messages_.get(), 3);
  const int bytes = sqlite3_column_bytes(messages_.get(), 3);
  if (!options_.strict && SkipUndecodable(id, topic, blob, bytes)) return std::nullopt;
  BagMessage m{topic, static_cast<std::uint64_t>(t), static_cast<const std::uint8_t*>(blob), static_cast<std::size_t>(bytes),
               where};
  return visitor_->OnMessage(m);
}

}  // namespace ros2_sqlite_internal

std::optional<Error> StreamRos2Sqlite(const std::string& path, const BagReadOptions& options, BagVisitor* visitor) {
  return ros2_sqlite_internal::Ros2SqliteReader(path, options, visitor).Run();
}

}  // namespace gyrocomp
