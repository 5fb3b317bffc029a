// rosbag2 sqlite3 storage reader (include/gyrocomp/io/bag.h): ros2/rosbag2,
// rosbag2_storage_default_plugins / rosbag2_storage_sqlite3, sqlite_storage.cpp, which creates
//     CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
//                         serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL)
//     CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,
//                           timestamp INTEGER NOT NULL, data BLOB NOT NULL)
// (later versions add a 'schema' / 'metadata' table and more topic columns; only the columns
// above are read). messages.timestamp is the receive time in ns; data is the CDR message as
// the rmw serialized it (serialization_format "cdr"). Messages are visited in id (insertion)
// order, one row at a time (sqlite3_step), with the topic filter in the query, so only wanted
// rows are read.
#include <sqlite3.h>

#include <memory>

#include "gyrocomp/io/bag.h"

namespace gyrocomp {

namespace {

using Db = std::unique_ptr<sqlite3, decltype(&sqlite3_close)>;
using Stmt = std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)>;

Error SqlError(const std::string& path, sqlite3* db, const std::string& what) {
  return InvalidInput(path + ": " + what + ": " + (db ? sqlite3_errmsg(db) : "cannot open") +
                      " (not a rosbag2 sqlite3 file?)");
}

std::string Text(sqlite3_stmt* s, int col) {
  const unsigned char* t = sqlite3_column_text(s, col);
  return t ? reinterpret_cast<const char*>(t) : "";
}

}  // namespace

std::optional<Error> StreamRos2Sqlite(const std::string& path, const BagReadOptions& /*options*/, BagVisitor* visitor) {
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
  Db db(raw, &sqlite3_close);
  if (rc != SQLITE_OK) return IoError(path + ": cannot open as sqlite3: " + (raw ? sqlite3_errmsg(raw) : "out of memory"));
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db.get(), "SELECT id, name, type, serialization_format FROM topics", -1, &st, nullptr) != SQLITE_OK) {
    return SqlError(path, db.get(), "reading table 'topics'");
  }
  Stmt topics(st, &sqlite3_finalize);
  int step = 0;
  while ((step = sqlite3_step(topics.get())) == SQLITE_ROW) {
    BagChannel ch;
    ch.id = static_cast<std::uint64_t>(sqlite3_column_int64(topics.get(), 0));
    ch.topic = Text(topics.get(), 1);
    ch.type = Text(topics.get(), 2);
    ch.encoding = Text(topics.get(), 3);
    if (auto e = visitor->OnChannel(ch)) return e;
  }
  if (step != SQLITE_DONE) return SqlError(path, db.get(), "reading table 'topics'");
  // Every message's topic and time (for counts), its data only when wanted: the data column is
  // read lazily by sqlite3_column_blob, so skipped rows cost their row header only.
  if (sqlite3_prepare_v2(db.get(), "SELECT id, topic_id, timestamp, data FROM messages ORDER BY id", -1, &st, nullptr) != SQLITE_OK) {
    return SqlError(path, db.get(), "reading table 'messages'");
  }
  Stmt messages(st, &sqlite3_finalize);
  while ((step = sqlite3_step(messages.get())) == SQLITE_ROW) {
    const sqlite3_int64 id = sqlite3_column_int64(messages.get(), 0);
    const auto topic = static_cast<std::uint64_t>(sqlite3_column_int64(messages.get(), 1));
    const sqlite3_int64 t = sqlite3_column_int64(messages.get(), 2);
    BagPosition where;
    where.message_id = id;
    if (t < 0) return InvalidInput(path + ": " + where.ToString() + ": negative timestamp " + std::to_string(t));
    visitor->Count(topic, static_cast<std::uint64_t>(t));
    if (!visitor->Wants(topic)) continue;
    const void* blob = sqlite3_column_blob(messages.get(), 3);
    const int bytes = sqlite3_column_bytes(messages.get(), 3);
    BagMessage m{topic, static_cast<std::uint64_t>(t), static_cast<const std::uint8_t*>(blob),
                 static_cast<std::size_t>(bytes), where};
    if (auto e = visitor->OnMessage(m)) return e;
  }
  if (step != SQLITE_DONE) return SqlError(path, db.get(), "reading table 'messages'");
  return std::nullopt;
}

}  // namespace gyrocomp
