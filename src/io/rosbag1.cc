// ROS 1 bag reader (include/gyrocomp/io/bag.h): the file read once in order, chunk by chunk
// (rosbag1_reader.h says how); recovery from damaged records in rosbag1_recovery.cc.
#include <algorithm>
#include <cstring>
#include <fstream>

#include "rosbag1_reader.h"

namespace gyrocomp {
namespace ros1_internal {

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

}  // namespace ros1_internal

std::optional<Error> StreamRos1Bag(std::istream& in, const std::string& source, const BagReadOptions& options,
                                   BagVisitor* visitor) {
  bag_internal::StreamSource bytes(in);
  if (!bytes.ok()) return IoError(source + ": cannot read (not seekable)");
  ros1_internal::Ros1Reader reader(bytes, source, options, visitor);
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
  ros1_internal::Ros1Reader reader(bytes, path, options, visitor);
  return reader.Run();
}

}  // namespace gyrocomp
