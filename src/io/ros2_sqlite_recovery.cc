// rosbag2 sqlite3 recovery (BagReadOptions::strict false); the reader's class is in
// ros2_sqlite_reader.h. SQLite gives no byte offsets and keeps no checksum of a row, so damage is
// what SQLite itself finds (a b-tree page that does not parse, checked harder with
// cell_size_check; a page the file's end cuts, ros2_sqlite_vfs.cc), a row with a NULL column, or
// a wanted row whose data do not decode as its topic's CDR message. After a
// damaged page the table is sought again at the next message ids (`id >= X` descends the b-tree
// afresh, so it lands past the damaged page once X is past the ids that page held): one id at a
// time for the first kLinearIds, then in doubling steps and a bisection back to the first id that
// reads, so the search is bounded (at most about 64 + 2 x 64 seeks) however the ids are spread.
// Only rows SQLite reads whole are kept, unchanged; an intact stretch of rows between two damaged
// pages inside one doubling step is lost with them. rosbag2 numbers messages 1, 2, 3, ...: the
// ids skipped are counted as messages lost, of unknown topic (their rows cannot be read).
#include <algorithm>
#include <limits>

#include "gyrocomp/io/cdr.h"
#include "ros2_sqlite_reader.h"

namespace gyrocomp::ros2_sqlite_internal {

namespace {

constexpr sqlite3_int64 kLinearIds = 64;  // ids sought one by one after a damaged page
constexpr sqlite3_int64 kMaxId = std::numeric_limits<sqlite3_int64>::max();

sqlite3_int64 Plus(sqlite3_int64 a, sqlite3_int64 b) { return a > kMaxId - b ? kMaxId : a + b; }  // b >= 0, saturating

}  // namespace

// The messages statement on its first row with id >= from: SQLITE_ROW, SQLITE_DONE (no such row)
// or the error. A row below `from` (a damaged page read as a valid one) is damage too.
int Ros2SqliteReader::Seek(sqlite3_int64 from) {
  sqlite3_reset(messages_.get());
  sqlite3_bind_int64(messages_.get(), 1, from);
  const int rc = sqlite3_step(messages_.get());
  if (rc == SQLITE_ROW && sqlite3_column_int64(messages_.get(), 0) < from) return SQLITE_CORRUPT;
  return rc;
}

// The smallest id >= from where Seek reads (a row or the table's end), in *at; the damage code
// when none up to the largest id does.
int Ros2SqliteReader::SeekReadable(sqlite3_int64 from, sqlite3_int64* at) {
  int rc = SQLITE_CORRUPT;
  for (sqlite3_int64 k = 0; k < kLinearIds && IsDamage(rc); ++k) {
    *at = Plus(from, k);
    rc = Seek(*at);
  }
  if (!IsDamage(rc)) return rc;
  sqlite3_int64 bad = *at, good = bad;  // Seek(bad) is damaged
  for (sqlite3_int64 step = kLinearIds; IsDamage(rc); step = Plus(step, step)) {
    if (bad == kMaxId) return rc;
    good = Plus(bad, step);
    rc = Seek(good);
    if (IsDamage(rc)) bad = good;
  }
  if (rc != SQLITE_ROW && rc != SQLITE_DONE) return rc;  // an I/O error: the caller's
  while (good - bad > 1) {
    const sqlite3_int64 mid = bad + (good - bad) / 2;
    if (IsDamage(Seek(mid))) {
      bad = mid;
    } else {
      good = mid;
    }
  }
  *at = good;
  return Seek(good);
}

// Reading found damage after row `last` (none read yet: nullopt): the ids from last + 1 up to the
// next row that reads are recorded lost, and the statement is left on that row (SQLITE_ROW), or
// at the end (SQLITE_DONE; also when nothing after could be read, the damage then open-ended);
// another error code (I/O) is returned for the caller to refuse.
int Ros2SqliteReader::ReadOnAfter(std::optional<sqlite3_int64> last, const std::string& why) {
  if (last && *last == kMaxId) return SQLITE_DONE;
  const sqlite3_int64 from = std::max<sqlite3_int64>(last ? *last + 1 : 1, 1);  // rosbag2's ids start at 1
  sqlite3_int64 at = from;
  const int rc = SeekReadable(from, &at);
  LogDamage d(static_cast<std::size_t>(from), static_cast<std::size_t>(from), "unreadable: " + why);
  d.message_ids = true;
  if (rc == SQLITE_ROW) at = sqlite3_column_int64(messages_.get(), 0);
  if (rc == SQLITE_ROW || rc == SQLITE_DONE) {
    d.end = static_cast<std::size_t>(at);
    // Between two rows read, every id was a message (rosbag2's numbering); before the table's
    // end, how many ids were used cannot be told: at least the row that failed.
    d.records_unidentified = rc == SQLITE_ROW ? d.end - d.begin : 1;
  } else if (IsDamage(rc)) {
    d.records_unidentified = 1;  // at least the row that failed; how many more cannot be told
  } else {
    return rc;  // not damage (an I/O error): the caller refuses
  }
  if (d.end > d.begin || IsDamage(rc)) damage_.push_back(std::move(d));
  return IsDamage(rc) ? SQLITE_DONE : rc;
}

// rosbag2 declares every column NOT NULL: a row without them (or with a text or number where
// the data blob belongs) is a record SQLite read from damaged bytes, its fields zeroed, not a
// message. Recorded lost, of unknown topic.
bool Ros2SqliteReader::SkipIncomplete(sqlite3_int64 id) {
  sqlite3_stmt* st = messages_.get();
  if (sqlite3_column_type(st, 1) == SQLITE_INTEGER && sqlite3_column_type(st, 2) == SQLITE_INTEGER &&
      sqlite3_column_type(st, 3) == SQLITE_BLOB) {
    return false;
  }
  LogDamage d(static_cast<std::size_t>(id), static_cast<std::size_t>(id) + 1, "a column of the row is NULL or of the wrong type");
  d.message_ids = true;
  d.records_unidentified = 1;
  damage_.push_back(std::move(d));
  return true;
}

// A wanted row whose data do not decode as its topic's message (the types ReadBagImu decodes):
// recorded lost on that topic. A row SQLite read whole can still hold damaged bytes, as SQLite
// keeps no checksum; this is the only sign of it.
bool Ros2SqliteReader::SkipUndecodable(sqlite3_int64 id, std::uint64_t topic_id, const void* blob, int bytes) {
  const auto it = topics_.find(topic_id);
  if (it == topics_.end() || it->second.encoding != "cdr") return false;
  const auto* data = static_cast<const std::uint8_t*>(blob);
  const auto size = static_cast<std::size_t>(bytes);
  std::optional<DecodeError> e;
  if (it->second.type == "sensor_msgs/msg/Imu" || it->second.type == "sensor_msgs/Imu") {
    ImuMessage m;
    e = DecodeCdrImu(data, size, &m);
  } else if (it->second.type == "sensor_msgs/msg/Temperature" || it->second.type == "sensor_msgs/Temperature") {
    TemperatureMessage m;
    e = DecodeCdrTemperature(data, size, &m);
  }
  if (!e) return false;
  LogDamage d(static_cast<std::size_t>(id), static_cast<std::size_t>(id) + 1,
              "topic " + it->second.name + ": message byte " + std::to_string(e->offset) + " of " + std::to_string(size) +
                  ": " + e->what);
  d.message_ids = true;
  d.rows_lost[it->second.name] = 1;
  damage_.push_back(std::move(d));
  return true;
}

// Each range once, in id order, at the end of the file (BagVisitor::OnDamage).
void Ros2SqliteReader::ReportDamage() {
  for (const LogDamage& d : damage_) visitor_->OnDamage(d);
}

}  // namespace gyrocomp::ros2_sqlite_internal
