// ROS 1 bag reader, format version 2.0 (include/gyrocomp/io/bag.h), written from the ROS wiki
// page "Bags/Format/2.0" (wiki.ros.org/Bags/Format/2.0). Quotes below are its section names.
//
// "Version": the file starts with the line "#ROSBAG V2.0\n".
// "Records": <header_len uint32><header><data_len uint32><data>; the header is a sequence of
//   fields <field_len uint32><name>=<value>; "op" (1 byte) gives the record's kind. Integers are
//   little-endian.
//   op 0x03 "Bag header": index_pos uint64, conn_count uint32, chunk_count uint32 (data: padding)
//   op 0x05 "Chunk": compression ("none", "bz2", "lz4"), size uint32 (uncompressed bytes); data:
//           the (compressed) connection and message data records
//   op 0x07 "Connection": conn uint32, topic; data: a connection header (fields topic, type,
//           md5sum, message_definition, ...)
//   op 0x02 "Message data": conn uint32, time uint64 (uint32 secs, uint32 nsecs: the receive
//           time); data: the ROS 1 serialized message
//   op 0x04 "Index data" (ver, conn, count), op 0x06 "Chunk info" (ver, chunk_pos, start_time,
//           end_time, count; data: conn uint32, count uint32 pairs): the index, not needed by a
//           sequential read.
// The whole file is read in order, chunk by chunk (unindexed bags, whose index_pos is 0, read the
// same); connection records repeated in the index section are announced once. "lz4" chunks are
// roslz4's, which writes the LZ4 frame format (ros_comm utilities/roslz4/src/lz4s.c).
//
// Recovery (BagReadOptions::strict false): a record whose header_len, header fields or data_len
// do not frame a record is skipped to the next offset where a record header parses, names a
// record kind ("op") with the fields that kind requires, and declares data within the file. A
// chunk that fails to decompress (bz2, lz4) or whose records do not parse loses its own messages
// and reading goes on after its data (or at the next record, when its data length was the
// damage); an uncompressed chunk's records are the file's bytes, so reading goes on at the next
// record inside it. The index section ("Chunk info": chunk_pos and messages per connection;
// "Connection") tells the messages a lost chunk held per topic, and the topic of a connection
// whose record was in a lost chunk.
#include <cstring>
#include <algorithm>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <string_view>
#include <utility>
#include <vector>

#include "bag_bytes.h"
#include "gyrocomp/io/bag.h"

namespace gyrocomp {

namespace {

using bag_internal::LoadLe;

constexpr char kVersionLine[] = "#ROSBAG V2.0\n";
constexpr std::size_t kVersionBytes = sizeof kVersionLine - 1;

enum Op : std::uint8_t {
  kMessageData = 0x02,
  kBagHeader = 0x03,
  kIndexData = 0x04,
  kChunk = 0x05,
  kChunkInfo = 0x06,
  kConnection = 0x07
};

// The fields of a record header (or a connection header) by name: views into the header's
// bytes, which outlive them (no allocation per record: a 3 h 200 Hz bag has 2 M of them).
class Fields {
 public:
  void clear() { items_.clear(); }
  void Add(std::string_view name, std::string_view value) { items_.emplace_back(name, value); }
  // The value of the last field of that name (a repeated name: the last one wins, as a map
  // assignment would), or nullopt.
  std::optional<std::string_view> Find(std::string_view name) const {
    for (auto it = items_.rbegin(); it != items_.rend(); ++it) {
      if (it->first == name) return it->second;
    }
    return std::nullopt;
  }

 private:
  std::vector<std::pair<std::string_view, std::string_view>> items_;
};

// Splits a header into fields; "" or the problem.
std::string ParseFields(const std::uint8_t* p, std::size_t n, Fields* out) {
  out->clear();
  std::size_t pos = 0;
  while (pos < n) {
    if (n - pos < 4) return "header ends inside a field length";
    const std::uint64_t len = LoadLe(p + pos, 4);
    pos += 4;
    if (len > n - pos) return "header field of " + std::to_string(len) + " bytes runs past the header's end";
    const std::string_view field(reinterpret_cast<const char*>(p + pos), static_cast<std::size_t>(len));
    pos += static_cast<std::size_t>(len);
    const std::size_t eq = field.find('=');
    if (eq == std::string_view::npos) return "header field without '=' (\"Records\": name=value)";
    out->Add(field.substr(0, eq), field.substr(eq + 1));
  }
  return "";
}

bool FieldInt(const Fields& f, const char* name, std::size_t bytes, std::uint64_t* v) {
  const std::optional<std::string_view> value = f.Find(name);
  if (!value || value->size() != bytes) return false;
  *v = LoadLe(reinterpret_cast<const std::uint8_t*>(value->data()), bytes);
  return true;
}

// "Records": whether the fields of a record header name a record kind this reader knows with the
// fields that kind requires ("Message data": conn, time; "Index data": ver, conn, count; "Chunk":
// compression, size; "Chunk info": ver, chunk_pos, start_time, end_time, count; "Connection":
// conn, topic). The bag header (op 0x03) only starts the file, so it is not a record to
// resynchronise at.
bool IsResyncRecord(const Fields& f) {
  std::uint64_t op = 0, v = 0;
  if (!FieldInt(f, "op", 1, &op)) return false;
  switch (op) {
    case kMessageData: return FieldInt(f, "conn", 4, &v) && FieldInt(f, "time", 8, &v);
    case kIndexData: return FieldInt(f, "ver", 4, &v) && FieldInt(f, "conn", 4, &v) && FieldInt(f, "count", 4, &v);
    case kChunk: {
      const std::optional<std::string_view> c = f.Find("compression");
      return c && (*c == "none" || *c == "bz2" || *c == "lz4") && FieldInt(f, "size", 4, &v);
    }
    case kChunkInfo:
      return FieldInt(f, "ver", 4, &v) && FieldInt(f, "chunk_pos", 8, &v) && FieldInt(f, "start_time", 8, &v) &&
             FieldInt(f, "end_time", 8, &v) && FieldInt(f, "count", 4, &v);
    case kConnection: return FieldInt(f, "conn", 4, &v) && f.Find("topic").has_value();
    default: return false;
  }
}

// Largest record header a resynchronising scan accepts: real headers are tens of bytes (a
// connection record's holds its topic name), so a damaged length is not followed far.
constexpr std::uint64_t kMaxResyncHeader = 64 * 1024;

// Whether the `avail` bytes at p start a record that IsResyncRecord accepts, whose header and
// data fit in the `left` bytes of the file from p.
bool RecordStartsAt(const std::uint8_t* p, std::uint64_t avail, std::uint64_t left, Fields* scratch) {
  if (avail < 8) return false;
  const std::uint64_t header_len = LoadLe(p, 4);
  // The shortest header is one field "op=X": 4 length bytes + 4 bytes.
  if (header_len < 8 || header_len > kMaxResyncHeader || header_len + 8 > avail) return false;
  const std::uint64_t data_len = LoadLe(p + 4 + header_len, 4);
  if (data_len > left - 8 - header_len) return false;
  return ParseFields(p + 4, static_cast<std::size_t>(header_len), scratch).empty() && IsResyncRecord(*scratch);
}

// A damaged record found by a handler: the strict error and, in recovery, where reading goes on.
struct Damage {
  BagPosition where;  // the record (and byte in its chunk) the strict error names
  std::string what;   // the strict error's text after the position
  std::uint64_t begin = 0;  // first byte skipped
  // Reading goes on at `resume` when a valid record starts there (or the file ends there), else
  // at the next valid record after `scan_from`.
  std::optional<std::uint64_t> resume;
  std::uint64_t scan_from = 0;
  std::optional<std::uint64_t> chunk;  // offset of the chunk record whose messages it loses
};

class Ros1Reader {
 public:
  Ros1Reader(bag_internal::ByteSource& bytes, const std::string& source, const BagReadOptions& options,
             BagVisitor* visitor)
      : bytes_(bytes), source_(source), options_(options), visitor_(visitor) {}
  std::optional<Error> Run();

 private:
  Error Bad(const BagPosition& where, const std::string& what) const {
    return InvalidInput(source_ + ": " + where.ToString() + ": " + what);
  }
  Error ReadError(std::uint64_t offset) const { return IoError(source_ + ": read error at " + At(offset).ToString()); }
  static BagPosition At(std::uint64_t offset) { return BagPosition{offset, {}, {}}; }
  // One record of the file at `pos`: sets *next to the record after it, or *damage.
  std::optional<Error> TopRecord(std::uint64_t pos, bool first, std::uint64_t* next, std::optional<Damage>* damage);
  // One record in memory (a chunk's content, or the data of a record of the file): its op,
  // header fields, data. A record that cannot be read sets *why.
  std::optional<Error> InnerRecord(const BagPosition& where, const Fields& f, const std::uint8_t* data, std::size_t n,
                                   std::string* why);
  std::optional<Error> Chunk(std::uint64_t at, const Fields& f, std::uint64_t data_at, std::uint64_t data_len,
                             std::optional<Damage>* damage);
  std::optional<Error> ChunkRecords(std::uint64_t at, const std::uint8_t* chunk, std::size_t n, std::size_t* bad_at,
                                    std::string* why);
  std::optional<Error> Connection(const BagPosition& where, const Fields& f, const std::uint8_t* data, std::size_t n,
                                  std::string* why);
  std::optional<Error> Message(const BagPosition& where, const Fields& f, const std::uint8_t* data, std::size_t n,
                               std::string* why);
  void ReadIndex(const Fields& bag_header);
  void AddChunkInfo(std::uint64_t chunk_pos, const std::uint8_t* data, std::uint64_t n);
  std::optional<Error> ChunkInfo(const Fields& f, std::uint64_t data_at, std::uint64_t data_len);
  // Recovery: the next offset >= from where a record starts (RecordStartsAt), or the file's size.
  std::uint64_t NextRecord(std::uint64_t from);
  bool ResumesAt(std::uint64_t pos);
  void AddDamage(const Damage& d, std::uint64_t end);
  void CountDelivered(const BagPosition& where, std::uint64_t conn);
  std::string TopicOf(std::uint64_t conn) const;
  void ReportDamage();
  void FitToIndexTotals(std::vector<std::map<std::uint64_t, std::uint64_t>>* lost) const;

  bag_internal::ByteSource& bytes_;
  const std::string& source_;
  const BagReadOptions& options_;
  BagVisitor* visitor_;
  std::set<std::uint64_t> connections_;
  std::map<std::uint64_t, std::uint64_t> expected_;  // messages per connection, from the index
  // From the index section ("Chunk info", "Connection"): each chunk's message count per
  // connection by the chunk record's offset, and every connection (topic, type).
  std::map<std::uint64_t, std::map<std::uint64_t, std::uint64_t>> chunk_counts_;
  std::uint64_t index_pos_ = 0;
  std::map<std::uint64_t, BagChannel> index_channels_;
  std::map<std::uint64_t, std::string> topics_;  // connection -> topic, of the connections read
  // Recovery: the skipped ranges, each with the chunk record it was found in (if any); the
  // messages read all the same of what each damage lost (index in damage_ -> connection ->
  // count): those of its chunk read before it, and those read outside chunks after it up to the
  // next chunk record (a resynchronising scan landed inside an uncompressed chunk); the
  // messages of the chunk being read. The losses are worked out at the file's end
  // (ReportDamage), when the index section has been read whatever happened to index_pos.
  std::vector<LogDamage> damage_;
  std::vector<std::optional<std::uint64_t>> damage_chunk_;
  std::map<std::size_t, std::map<std::uint64_t, std::uint64_t>> delivered_;
  std::map<std::uint64_t, std::uint64_t> chunk_delivered_;
  std::optional<std::size_t> open_damage_;  // the damage top-level messages are read after
  bool index_read_ = false;  // chunk_counts_ came from index_pos
  std::optional<std::uint64_t> header_chunk_count_;  // the bag header's chunk_count
  std::map<std::uint64_t, std::uint64_t> read_;  // messages read per connection (recovery)
  std::map<std::uint64_t, std::size_t> unknown_conn_damage_;  // connection -> index in damage_
  std::uint64_t record_end_ = 0;  // end of the file record being read (for damage ranges)
  // Scratch buffers of a stream source (a mapped file views its pages instead): the record
  // header, its data, a compressed chunk and its decompressed bytes, a resynchronising scan's
  // window. Separate, because the header fields are views into the header's bytes while the
  // data is read.
  std::vector<std::uint8_t> header_buf_, data_buf_, compressed_, chunk_, scan_buf_;
  Fields fields_, inner_fields_, scan_fields_;
};

std::optional<Error> Ros1Reader::Run() {
  const std::uint64_t size = bytes_.size();
  if (size < kVersionBytes) return Bad(At(0), "not a ROS 1 bag of version 2.0 (\"Version\": #ROSBAG V2.0)");
  const std::uint8_t* version = bytes_.View(0, kVersionBytes, &header_buf_);
  if (version == nullptr) return ReadError(0);
  if (std::memcmp(version, kVersionLine, kVersionBytes) != 0) {
    return Bad(At(0), "not a ROS 1 bag of version 2.0 (\"Version\": #ROSBAG V2.0)");
  }
  std::uint64_t pos = kVersionBytes;
  bool first = true;
  while (pos < size) {
    std::optional<Damage> damage;
    std::uint64_t next = size;
    if (auto e = TopRecord(pos, first, &next, &damage)) return e;
    first = false;
    if (damage) {
      if (options_.strict) return Bad(damage->where, damage->what);
      // Each step moves forward: the resume point and the scan start are past `pos`.
      next = damage->resume && ResumesAt(*damage->resume) ? *damage->resume : NextRecord(damage->scan_from);
      AddDamage(*damage, next);
    }
    pos = next;
    bytes_.Consumed(pos);
  }
  ReportDamage();
  return std::nullopt;
}

std::optional<Error> Ros1Reader::TopRecord(std::uint64_t pos, bool first, std::uint64_t* next,
                                           std::optional<Damage>* damage) {
  const std::uint64_t size = bytes_.size();
  // A record this reader cannot frame: skipped to the next record that parses.
  const auto unframed = [&](const std::string& what) {
    *damage = Damage{At(pos), what, pos, std::nullopt, pos + 1, std::nullopt};
    return std::nullopt;
  };
  if (size - pos < 4) return unframed("truncated record: the file ends inside its header length");
  const std::uint8_t* len_bytes = bytes_.View(pos, 4, &header_buf_);
  if (len_bytes == nullptr) return ReadError(pos);
  const std::uint64_t header_len = LoadLe(len_bytes, 4);
  if (header_len > size - pos - 4 || size - pos - 4 - header_len < 4) {
    return unframed("truncated record: a header of " + std::to_string(header_len) + " bytes and its data length "
                    "run past the end of the file");
  }
  if (header_len > options_.max_chunk_bytes) return unframed("record header of " + std::to_string(header_len) + " bytes: too large");
  const std::uint8_t* header = bytes_.View(pos + 4, static_cast<std::size_t>(header_len) + 4, &header_buf_);
  if (header == nullptr) return ReadError(pos);
  const std::uint64_t data_len = LoadLe(header + header_len, 4);
  const std::uint64_t data_at = pos + 8 + header_len;
  if (data_len > size - data_at) {
    return unframed("truncated record: " + std::to_string(data_len) + " data bytes declared, " +
                    std::to_string(size - data_at) + " left in the file");
  }
  Fields& f = fields_;
  if (std::string why = ParseFields(header, static_cast<std::size_t>(header_len), &f); !why.empty()) return unframed(why);
  std::uint64_t op = 0;
  if (!FieldInt(f, "op", 1, &op)) return unframed("record without a 1-byte 'op' header field");
  if (first && op != kBagHeader) return unframed("the first record is op " + std::to_string(op) + ", not the bag header (0x03)");
  if (first) ReadIndex(f);
  if (op < kMessageData || op > kConnection) {
    return unframed("record op " + std::to_string(op) + " is none of the bag 2.0 records (0x02-0x07)");
  }
  *next = data_at + data_len;
  record_end_ = *next;
  if (op == kChunk) return Chunk(pos, f, data_at, data_len, damage);
  if (op == kChunkInfo && !index_read_ && !options_.strict) return ChunkInfo(f, data_at, data_len);
  if (op != kConnection && op != kMessageData) return std::nullopt;
  if (data_len > options_.max_chunk_bytes) return unframed("record of " + std::to_string(data_len) + " bytes: too large");
  const std::uint8_t* data = bytes_.View(data_at, static_cast<std::size_t>(data_len), &data_buf_);
  if (data == nullptr) return ReadError(data_at);
  std::string why;
  if (auto e = InnerRecord(At(pos), f, data, static_cast<std::size_t>(data_len), &why)) return e;
  if (!why.empty()) return unframed(why);
  return std::nullopt;
}

std::optional<Error> Ros1Reader::Chunk(std::uint64_t at, const Fields& f, std::uint64_t data_at, std::uint64_t data_len,
                                       std::optional<Damage>* damage) {
  const std::uint64_t data_end = data_at + data_len;
  // A chunk that cannot be read loses its messages; reading goes on after its data when a record
  // starts there, else at the next record after its header (its length may be the damage).
  const auto lost = [&](const BagPosition& where, const std::string& what) {
    *damage = Damage{where, what, at, data_end, data_at, at};
    return std::nullopt;
  };
  chunk_delivered_.clear();
  open_damage_.reset();  // messages from here on are this chunk's
  std::uint64_t usize = 0;
  const std::optional<std::string_view> comp = f.Find("compression");
  if (!comp || !FieldInt(f, "size", 4, &usize)) {
    return lost(At(at), "chunk record without its 'compression' and 4-byte 'size' fields");
  }
  const std::string method(*comp);
  if (method != "none" && method != "bz2" && method != "lz4") {
    return lost(At(at), "chunk compression '" + method + "' is not one of none, bz2, lz4 (\"Chunk\")");
  }
  if (usize > options_.max_chunk_bytes || data_len > options_.max_chunk_bytes) {
    return lost(At(at), "chunk declares " + std::to_string(usize) + " uncompressed bytes (" + std::to_string(data_len) +
                            " stored): more than the " + std::to_string(options_.max_chunk_bytes) +
                            "-byte limit (BagReadOptions::max_chunk_bytes); refused as a possible compression bomb");
  }
  if (method == "none" && usize != data_len) {
    return lost(At(at), "uncompressed chunk declares " + std::to_string(usize) + " bytes but holds " + std::to_string(data_len));
  }
  const std::uint8_t* stored = bytes_.View(data_at, static_cast<std::size_t>(data_len), &compressed_);
  if (stored == nullptr) return ReadError(data_at);
  const std::uint8_t* records = stored;
  if (method != "none") {
    chunk_.assign(static_cast<std::size_t>(usize), 0);
    const std::string why = bag_internal::Decompress(method, stored, static_cast<std::size_t>(data_len), &chunk_);
    // A bz2 / lz4 chunk that fails to decompress: all its messages are lost.
    if (!why.empty()) return lost(At(at), "chunk: " + why);
    records = chunk_.data();
  }
  std::size_t bad_at = 0;
  std::string why;
  if (auto e = ChunkRecords(at, records, static_cast<std::size_t>(usize), &bad_at, &why)) return e;
  if (why.empty()) return std::nullopt;
  const BagPosition where{at, bad_at, {}};
  if (method != "none") return lost(where, why);  // the rest of a decompressed chunk is lost
  // An uncompressed chunk's records are the file's bytes: reading goes on at the next record
  // that parses after the damaged one (maybe one of this chunk).
  *damage = Damage{where, why, data_at + bad_at, std::nullopt, data_at + bad_at + 1, at};
  return std::nullopt;
}

// The chunk's records, same layout as the file's. A record that cannot be read stops them, with
// its chunk byte in *bad_at.
std::optional<Error> Ros1Reader::ChunkRecords(std::uint64_t at, const std::uint8_t* chunk, std::size_t n,
                                              std::size_t* bad_at, std::string* why) {
  std::size_t pos = 0;
  while (pos < n && why->empty()) {
    *bad_at = pos;
    const BagPosition where{at, pos, {}};
    if (n - pos < 4) {
      *why = "truncated record inside the chunk";
      break;
    }
    const std::uint64_t header_len = LoadLe(chunk + pos, 4);
    if (header_len > n - pos - 4 || n - pos - 4 - header_len < 4) {
      *why = "record header runs past the chunk's end";
      break;
    }
    const std::uint8_t* header = chunk + pos + 4;
    const std::uint64_t data_len2 = LoadLe(header + header_len, 4);
    const std::size_t data_pos = pos + 8 + static_cast<std::size_t>(header_len);
    if (data_len2 > n - data_pos) {
      *why = "record data of " + std::to_string(data_len2) + " bytes runs past the chunk's end";
      break;
    }
    *why = ParseFields(header, static_cast<std::size_t>(header_len), &inner_fields_);
    if (!why->empty()) break;
    if (auto e = InnerRecord(where, inner_fields_, chunk + data_pos, static_cast<std::size_t>(data_len2), why)) return e;
    pos = data_pos + static_cast<std::size_t>(data_len2);
  }
  return std::nullopt;
}

std::optional<Error> Ros1Reader::InnerRecord(const BagPosition& where, const Fields& f, const std::uint8_t* data,
                                             std::size_t n, std::string* why) {
  std::uint64_t op = 0;
  if (!FieldInt(f, "op", 1, &op)) {
    *why = "record without a 1-byte 'op' header field";
    return std::nullopt;
  }
  if (op == kConnection) return Connection(where, f, data, n, why);
  if (op == kMessageData) return Message(where, f, data, n, why);
  // "Chunk": a chunk holds connection and message data records only.
  if (where.chunk_byte) *why = "record op " + std::to_string(op) + " inside a chunk (only 0x02 and 0x07 belong there)";
  return std::nullopt;
}

std::optional<Error> Ros1Reader::Message(const BagPosition& where, const Fields& f, const std::uint8_t* data,
                                         std::size_t n, std::string* why) {
  std::uint64_t conn = 0, time = 0;
  if (!FieldInt(f, "conn", 4, &conn) || !FieldInt(f, "time", 8, &time)) {
    *why = "message data record without its 4-byte 'conn' and 8-byte 'time' fields";
    return std::nullopt;
  }
  // "time": uint32 secs then uint32 nsecs.
  const std::uint64_t secs = time & 0xffffffffu, nsecs = time >> 32;
  if (nsecs >= 1000000000u) {
    *why = "message time nsecs = " + std::to_string(nsecs) + " is not below 1e9";
    return std::nullopt;
  }
  if (connections_.count(conn) == 0) {
    // Its connection record was in a chunk that was lost: the index section repeats it.
    if (const auto it = index_channels_.find(conn); !options_.strict && it != index_channels_.end()) {
      connections_.insert(conn);
      topics_[conn] = it->second.topic;
      if (auto e = visitor_->OnChannel(it->second)) return e;
    } else if (options_.strict) {
      *why = "message on connection " + std::to_string(conn) + ", which no connection record defined before it";
      return std::nullopt;
    } else {
      // No topic to give it: one damage entry per such connection counts its messages.
      auto [d, added] = unknown_conn_damage_.emplace(conn, damage_.size());
      if (added) {
        damage_.emplace_back(where.offset, record_end_, "messages on connection " + std::to_string(conn) +
                                                            ", whose connection record was lost");
        damage_chunk_.emplace_back();
      }
      damage_[d->second].end = record_end_;
      ++damage_[d->second].rows_lost["connection " + std::to_string(conn)];
      ++read_[conn];  // counted here, not again against the index
      return std::nullopt;
    }
  }
  const std::uint64_t receive_ns = secs * 1000000000u + nsecs;
  CountDelivered(where, conn);
  visitor_->Count(conn, receive_ns);
  if (!visitor_->Wants(conn)) return std::nullopt;
  return visitor_->OnMessage(BagMessage{conn, receive_ns, data, n, where});
}

// The index section ("Chunk info" and "Connection" records after index_pos): each chunk's
// message count per connection (a hint for reserving memory, and in recovery the messages a
// lost chunk held) and each connection (in recovery, for messages whose connection record was
// in a lost chunk). Anything odd (no index, a record that does not parse) leaves them incomplete
// or empty, never an error: the sequential read checks every byte it uses. Each count is capped
// at the number of message records the file could hold (a hostile index cannot make a reader
// reserve more).
void Ros1Reader::ReadIndex(const Fields& bag_header) {
  std::uint64_t index_pos = 0, chunk_count = 0;
  const std::uint64_t size = bytes_.size();
  if (FieldInt(bag_header, "chunk_count", 4, &chunk_count)) header_chunk_count_ = chunk_count;
  if (!FieldInt(bag_header, "index_pos", 8, &index_pos) || index_pos == 0 || index_pos >= size) return;
  index_pos_ = index_pos;
  std::vector<std::uint8_t> header_buf, data_buf;
  Fields f, conn_header;
  for (std::uint64_t pos = index_pos; size - pos >= 8;) {
    const std::uint8_t* len = bytes_.View(pos, 4, &header_buf);
    if (len == nullptr) break;
    const std::uint64_t header_len = LoadLe(len, 4);
    if (header_len > size - pos - 4 || size - pos - 4 - header_len < 4 || header_len > options_.max_chunk_bytes) break;
    const std::uint8_t* header = bytes_.View(pos + 4, static_cast<std::size_t>(header_len) + 4, &header_buf);
    if (header == nullptr) break;
    const std::uint64_t data_len = LoadLe(header + header_len, 4);
    const std::uint64_t data_at = pos + 8 + header_len;
    std::uint64_t op = 0, chunk_pos = 0, conn = 0;
    if (data_len > size - data_at || data_len > options_.max_chunk_bytes ||
        !ParseFields(header, static_cast<std::size_t>(header_len), &f).empty() || !FieldInt(f, "op", 1, &op)) {
      break;
    }
    const bool info = op == kChunkInfo && data_len % 8 == 0 && FieldInt(f, "chunk_pos", 8, &chunk_pos);
    const bool connection = op == kConnection && FieldInt(f, "conn", 4, &conn) && f.Find("topic");
    if (info || connection) {
      const std::uint8_t* d = bytes_.View(data_at, static_cast<std::size_t>(data_len), &data_buf);
      if (d == nullptr) break;
      if (info) AddChunkInfo(chunk_pos, d, data_len);
      if (connection && ParseFields(d, static_cast<std::size_t>(data_len), &conn_header).empty()) {
        BagChannel& ch = index_channels_[conn];
        ch = BagChannel{conn, std::string(*f.Find("topic")), std::string(conn_header.Find("type").value_or("")), "ros1", {}};
      }
    }
    pos = data_at + data_len;
  }
  index_read_ = !chunk_counts_.empty();
  for (auto& [conn, ch] : index_channels_) {
    if (const auto it = expected_.find(conn); it != expected_.end()) ch.expected_messages = it->second;
  }
}

// "Chunk info" data: (conn uint32, count uint32) pairs. A message data record is at least 8
// length bytes and three fields (op, conn, time), 45 bytes: no count exceeds what the file holds.
void Ros1Reader::AddChunkInfo(std::uint64_t chunk_pos, const std::uint8_t* d, std::uint64_t n) {
  const std::uint64_t most = bytes_.size() / 45;
  for (std::uint64_t k = 0; k + 8 <= n; k += 8) {
    std::uint64_t& total = expected_[LoadLe(d + k, 4)];
    total = std::min(most, total + LoadLe(d + k + 4, 4));
    std::uint64_t& count = chunk_counts_[chunk_pos][LoadLe(d + k, 4)];
    count = std::min(most, count + LoadLe(d + k + 4, 4));
  }
}

// A "Chunk info" record met in the file (recovery, when index_pos did not lead to the index).
std::optional<Error> Ros1Reader::ChunkInfo(const Fields& f, std::uint64_t data_at, std::uint64_t data_len) {
  std::uint64_t chunk_pos = 0;
  if (!FieldInt(f, "chunk_pos", 8, &chunk_pos) || data_len % 8 != 0 || data_len > options_.max_chunk_bytes) return std::nullopt;
  const std::uint8_t* d = bytes_.View(data_at, static_cast<std::size_t>(data_len), &data_buf_);
  if (d == nullptr) return ReadError(data_at);
  AddChunkInfo(chunk_pos, d, data_len);
  return std::nullopt;
}

std::optional<Error> Ros1Reader::Connection(const BagPosition& /*where*/, const Fields& f, const std::uint8_t* data,
                                            std::size_t n, std::string* why) {
  std::uint64_t conn = 0;
  const std::optional<std::string_view> topic = f.Find("topic");
  if (!FieldInt(f, "conn", 4, &conn) || !topic) {
    *why = "connection record without its 4-byte 'conn' and 'topic' fields";
    return std::nullopt;
  }
  Fields header;
  if (std::string bad = ParseFields(data, n, &header); !bad.empty()) {
    *why = "connection header: " + bad;
    return std::nullopt;
  }
  if (!connections_.insert(conn).second) return std::nullopt;
  BagChannel ch;
  ch.id = conn;
  ch.topic = std::string(*topic);
  ch.type = std::string(header.Find("type").value_or(""));
  ch.encoding = "ros1";
  topics_[conn] = ch.topic;
  if (const auto it = expected_.find(conn); it != expected_.end()) ch.expected_messages = it->second;
  return visitor_->OnChannel(ch);
}

// ---- Recovery ----

bool Ros1Reader::ResumesAt(std::uint64_t pos) {
  const std::uint64_t size = bytes_.size();
  if (pos == size) return true;
  if (pos > size || size - pos < 8) return false;
  const std::uint64_t avail = std::min<std::uint64_t>(size - pos, kMaxResyncHeader + 8);
  const std::uint8_t* p = bytes_.View(pos, static_cast<std::size_t>(avail), &scan_buf_);
  return p != nullptr && RecordStartsAt(p, avail, size - pos, &scan_fields_);
}

// Scans windows of 1 MiB (plus room for one header) for the first offset where a record starts.
std::uint64_t Ros1Reader::NextRecord(std::uint64_t from) {
  constexpr std::uint64_t kStep = std::uint64_t{1} << 20;
  const std::uint64_t size = bytes_.size();
  for (std::uint64_t base = from; base < size; base += kStep) {
    const std::uint64_t avail = std::min<std::uint64_t>(size - base, kStep + kMaxResyncHeader + 8);
    const std::uint8_t* w = bytes_.View(base, static_cast<std::size_t>(avail), &scan_buf_);
    if (w == nullptr) return size;  // unreadable: the rest is skipped as damage
    const std::uint64_t stop = std::min<std::uint64_t>(avail, kStep);
    for (std::uint64_t k = 0; k < stop; ++k) {
      if (RecordStartsAt(w + k, avail - k, size - base - k, &scan_fields_)) return base + k;
    }
    bytes_.Consumed(base);
  }
  return size;
}

// A message read: counted against its chunk, or the damage it follows (whose loss is then smaller).
void Ros1Reader::CountDelivered(const BagPosition& where, std::uint64_t conn) {
  if (options_.strict) return;
  ++read_[conn];
  if (where.chunk_byte) {
    ++chunk_delivered_[conn];
  } else if (open_damage_) {
    ++delivered_[*open_damage_][conn];
  }
}

// The range [d.begin, end) skipped (its losses: ReportDamage).
void Ros1Reader::AddDamage(const Damage& d, std::uint64_t end) {
  open_damage_ = damage_.size();
  damage_.emplace_back(d.begin, std::max(end, d.begin), d.what);
  damage_chunk_.push_back(d.chunk);
  if (d.chunk) delivered_[*open_damage_] = chunk_delivered_;
}

std::string Ros1Reader::TopicOf(std::uint64_t conn) const {
  if (const auto it = topics_.find(conn); it != topics_.end()) return it->second;
  if (const auto it = index_channels_.find(conn); it != index_channels_.end()) return it->second.topic;
  return "connection " + std::to_string(conn);
}

// Rows lost per topic. A damage loses the chunk it was found in and every chunk the index puts
// in its byte range (the first damage to reach a chunk counts it): their counts in the index
// less the messages read all the same. A deleted or inserted byte moves every record after it
// away from the offsets the index gives, so when the index lists every chunk (the bag header's
// chunk_count) the losses are made to add up to what it counts less what was read
// (FitToIndexTotals). With no index entry for a damage the loss cannot be told by topic.
void Ros1Reader::ReportDamage() {
  std::set<std::uint64_t> counted;  // chunk offsets
  std::vector<std::map<std::uint64_t, std::uint64_t>> lost(damage_.size());  // per damage: connection -> messages
  for (std::size_t i = 0; i < damage_.size(); ++i) {
    LogDamage& d = damage_[i];
    std::map<std::uint64_t, std::uint64_t> expected;  // connection -> messages
    bool told = false;
    const auto lose = [&](std::uint64_t chunk) {
      const auto it = chunk_counts_.find(chunk);
      if (it == chunk_counts_.end()) return;
      told = true;
      if (!counted.insert(chunk).second) return;
      for (const auto& [conn, count] : it->second) expected[conn] += count;
    };
    const bool chunk_damage = damage_chunk_[i].has_value();
    if (chunk_damage) lose(*damage_chunk_[i]);
    for (auto it = chunk_counts_.lower_bound(d.begin); it != chunk_counts_.end() && it->first < d.end; ++it) lose(it->first);
    for (const auto& [conn, count] : expected) {
      const std::uint64_t got = delivered_[i][conn];
      if (count > got) lost[i][conn] = count - got;
    }
    if (!told && d.rows_lost.empty() && (chunk_damage || chunk_counts_.empty())) d.records_unidentified = 1;
  }
  if (header_chunk_count_ && chunk_counts_.size() == *header_chunk_count_) FitToIndexTotals(&lost);
  for (std::size_t i = 0; i < damage_.size(); ++i) {
    for (const auto& [conn, count] : lost[i]) {
      if (count > 0) damage_[i].rows_lost[TopicOf(conn)] += static_cast<std::size_t>(count);
    }
    visitor_->OnDamage(damage_[i]);
  }
}

// Per connection, the messages lost in all = the index's count less the messages read: losses
// counted beyond it are taken back from the last damages, losses not counted go to the first
// damage that lost a chunk (else the first damage).
void Ros1Reader::FitToIndexTotals(std::vector<std::map<std::uint64_t, std::uint64_t>>* lost) const {
  std::map<std::uint64_t, std::uint64_t> total;
  for (const auto& [chunk, counts] : chunk_counts_) {
    for (const auto& [conn, count] : counts) total[conn] += count;
  }
  std::size_t first = 0;
  for (std::size_t i = 0; i < damage_.size(); ++i) {
    if (damage_chunk_[i]) {
      first = i;
      break;
    }
  }
  for (const auto& [conn, count] : total) {
    const auto r = read_.find(conn);
    const std::uint64_t missing = count - std::min(count, r == read_.end() ? 0 : r->second);
    std::uint64_t counted = 0;
    for (const auto& l : *lost) counted += l.count(conn) ? l.at(conn) : 0;
    for (std::size_t i = lost->size(); i-- > 0 && counted > missing;) {
      std::uint64_t& n = (*lost)[i][conn];
      const std::uint64_t back = std::min(n, counted - missing);
      n -= back;
      counted -= back;
    }
    if (counted < missing && !lost->empty()) (*lost)[first][conn] += missing - counted;
  }
}

}  // namespace

std::optional<Error> StreamRos1Bag(std::istream& in, const std::string& source, const BagReadOptions& options,
                                   BagVisitor* visitor) {
  bag_internal::StreamSource bytes(in);
  if (!bytes.ok()) return IoError(source + ": cannot read (not seekable)");
  Ros1Reader reader(bytes, source, options, visitor);
  return reader.Run();
}

std::optional<Error> StreamRos1BagFile(const std::string& path, const BagReadOptions& options, BagVisitor* visitor) {
  Result<MappedFile> mapped = MappedFile::Open(path);
  if (!mapped.ok()) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return IoError(path + ": cannot open");
    return StreamRos1Bag(in, path, options, visitor);
  }
  bag_internal::MappedSource bytes(*mapped);
  Ros1Reader reader(bytes, path, options, visitor);
  return reader.Run();
}

}  // namespace gyrocomp
