// The rosbag2 sqlite3 reader's class, shared by ros2_sqlite.cc (reading) and
// ros2_sqlite_recovery.cc (reading on past damage); not installed.
#pragma once

#include <sqlite3.h>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gyrocomp/io/bag.h"

namespace gyrocomp::ros2_sqlite_internal {

using Db = std::unique_ptr<sqlite3, decltype(&sqlite3_close)>;
using Stmt = std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)>;

// A result code that means the database file is damaged (not an I/O error or a full memory).
inline bool IsDamage(int rc) { return (rc & 0xff) == SQLITE_CORRUPT || (rc & 0xff) == SQLITE_NOTADB; }

// The VFS to open a .db3 with: the default one, with a read past the end of the file reported as
// SQLITE_CORRUPT instead of zeros (ros2_sqlite_vfs.cc). Registered on first use.
const char* ShortReadIsDamageVfs();

// One .db3 read from start to end: its topics, then its messages in id order.
class Ros2SqliteReader {
 public:
  Ros2SqliteReader(const std::string& path, const BagReadOptions& options, BagVisitor* visitor)
      : path_(path), options_(options), visitor_(visitor) {}
  std::optional<Error> Run();

 private:
  std::optional<Error> ReadTopics();
  std::optional<Error> ReadMessages();
  // The row the messages statement is on: counted, and handed on when wanted.
  std::optional<Error> OnRow(sqlite3_int64 id);
  Error SqlError(const std::string& what) const;

  // Seeking and recovery (ros2_sqlite_recovery.cc).
  int Seek(sqlite3_int64 from);
  int SeekReadable(sqlite3_int64 from, sqlite3_int64* at);
  int ReadOnAfter(std::optional<sqlite3_int64> last, const std::string& why);
  bool SkipIncomplete(sqlite3_int64 id);
  bool SkipUndecodable(sqlite3_int64 id, std::uint64_t topic_id, const void* blob, int bytes);
  void ReportDamage();

  struct Topic {
    std::string name, type, encoding;
  };
  const std::string& path_;
  const BagReadOptions& options_;
  BagVisitor* visitor_;
  Db db_{nullptr, &sqlite3_close};
  Stmt messages_{nullptr, &sqlite3_finalize};  // SELECT ... FROM messages WHERE id >= ?1 ORDER BY id
  std::map<std::uint64_t, Topic> topics_;  // topics.id -> its row
  std::vector<LogDamage> damage_;  // message id ranges, in id order
};

}  // namespace gyrocomp::ros2_sqlite_internal
