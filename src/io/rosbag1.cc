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
//   op 0x04 "Index data", op 0x06 "Chunk info": the index, not needed by a sequential read.
// The whole file is read in order, chunk by chunk (unindexed bags, whose index_pos is 0, read the
// same); connection records repeated in the index section are announced once. "lz4" chunks are
// roslz4's, which writes the LZ4 frame format (ros_comm utilities/roslz4/src/lz4s.c).
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
  // One record in memory (a chunk's content): its op, header fields, data.
  std::optional<Error> InnerRecord(const BagPosition& where, const Fields& f, const std::uint8_t* data, std::size_t n);
  std::optional<Error> Chunk(std::uint64_t at, const Fields& f, std::uint64_t data_at, std::uint64_t data_len);
  std::optional<Error> ChunkRecords(std::uint64_t at, const std::uint8_t* chunk, std::size_t n);
  std::optional<Error> Connection(const BagPosition& where, const Fields& f, const std::uint8_t* data, std::size_t n);
  void ReadIndexCounts(const Fields& bag_header);

  bag_internal::ByteSource& bytes_;
  const std::string& source_;
  const BagReadOptions& options_;
  BagVisitor* visitor_;
  std::set<std::uint64_t> connections_;
  std::map<std::uint64_t, std::uint64_t> expected_;  // messages per connection, from the index
  // Scratch buffers of a stream source (a mapped file views its pages instead): the record
  // header, its data, a compressed chunk and its decompressed bytes. Separate, because the header
  // fields are views into the header's bytes while the data is read.
  std::vector<std::uint8_t> header_buf_, data_buf_, compressed_, chunk_;
  Fields fields_, inner_fields_;
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
    if (size - pos < 4) return Bad(At(pos), "truncated record: the file ends inside its header length");
    const std::uint8_t* len_bytes = bytes_.View(pos, 4, &header_buf_);
    if (len_bytes == nullptr) return ReadError(pos);
    const std::uint64_t header_len = LoadLe(len_bytes, 4);
    if (header_len > size - pos - 4 || size - pos - 4 - header_len < 4) {
      return Bad(At(pos), "truncated record: a header of " + std::to_string(header_len) + " bytes and its data length "
                              "run past the end of the file");
    }
    if (header_len > options_.max_chunk_bytes) return Bad(At(pos), "record header of " + std::to_string(header_len) + " bytes: too large");
    const std::uint8_t* header = bytes_.View(pos + 4, static_cast<std::size_t>(header_len) + 4, &header_buf_);
    if (header == nullptr) return ReadError(pos);
    const std::uint64_t data_len = LoadLe(header + header_len, 4);
    const std::uint64_t data_at = pos + 8 + header_len;
    if (data_len > size - data_at) {
      return Bad(At(pos), "truncated record: " + std::to_string(data_len) + " data bytes declared, " +
                              std::to_string(size - data_at) + " left in the file");
    }
    Fields& f = fields_;
    if (std::string why = ParseFields(header, static_cast<std::size_t>(header_len), &f); !why.empty()) {
      return Bad(At(pos), why);
    }
    std::uint64_t op = 0;
    if (!FieldInt(f, "op", 1, &op)) return Bad(At(pos), "record without a 1-byte 'op' header field");
    if (first && op != kBagHeader) return Bad(At(pos), "the first record is op " + std::to_string(op) + ", not the bag header (0x03)");
    if (first) ReadIndexCounts(f);
    first = false;
    if (op == kChunk) {
      if (auto e = Chunk(pos, f, data_at, data_len)) return e;
    } else if (op == kConnection || op == kMessageData) {
      if (data_len > options_.max_chunk_bytes) return Bad(At(pos), "record of " + std::to_string(data_len) + " bytes: too large");
      const std::uint8_t* data = bytes_.View(data_at, static_cast<std::size_t>(data_len), &data_buf_);
      if (data == nullptr) return ReadError(data_at);
      if (auto e = InnerRecord(At(pos), f, data, static_cast<std::size_t>(data_len))) return e;
    }
    pos = data_at + data_len;
    bytes_.Consumed(pos);
  }
  return std::nullopt;
}

std::optional<Error> Ros1Reader::Chunk(std::uint64_t at, const Fields& f, std::uint64_t data_at, std::uint64_t data_len) {
  std::uint64_t usize = 0;
  const std::optional<std::string_view> comp = f.Find("compression");
  if (!comp || !FieldInt(f, "size", 4, &usize)) {
    return Bad(At(at), "chunk record without its 'compression' and 4-byte 'size' fields");
  }
  const std::string method(*comp);
  if (method != "none" && method != "bz2" && method != "lz4") {
    return Bad(At(at), "chunk compression '" + method + "' is not one of none, bz2, lz4 (\"Chunk\")");
  }
  if (usize > options_.max_chunk_bytes || data_len > options_.max_chunk_bytes) {
    return Bad(At(at), "chunk declares " + std::to_string(usize) + " uncompressed bytes (" + std::to_string(data_len) +
                           " stored): more than the " + std::to_string(options_.max_chunk_bytes) +
                           "-byte limit (BagReadOptions::max_chunk_bytes); refused as a possible compression bomb");
  }
  if (method == "none" && usize != data_len) {
    return Bad(At(at), "uncompressed chunk declares " + std::to_string(usize) + " bytes but holds " + std::to_string(data_len));
  }
  const std::uint8_t* stored = bytes_.View(data_at, static_cast<std::size_t>(data_len), &compressed_);
  if (stored == nullptr) return ReadError(data_at);
  if (method == "none") return ChunkRecords(at, stored, static_cast<std::size_t>(data_len));
  chunk_.assign(static_cast<std::size_t>(usize), 0);
  const std::string why = bag_internal::Decompress(method, stored, static_cast<std::size_t>(data_len), &chunk_);
  if (!why.empty()) return Bad(At(at), "chunk: " + why);
  return ChunkRecords(at, chunk_.data(), chunk_.size());
}

// The chunk's records, same layout as the file's.
std::optional<Error> Ros1Reader::ChunkRecords(std::uint64_t at, const std::uint8_t* chunk, std::size_t n) {
  std::size_t pos = 0;
  while (pos < n) {
    const BagPosition where{at, pos, {}};
    if (n - pos < 4) return Bad(where, "truncated record inside the chunk");
    const std::uint64_t header_len = LoadLe(chunk + pos, 4);
    if (header_len > n - pos - 4 || n - pos - 4 - header_len < 4) return Bad(where, "record header runs past the chunk's end");
    const std::uint8_t* header = chunk + pos + 4;
    const std::uint64_t data_len2 = LoadLe(header + header_len, 4);
    const std::size_t data_pos = pos + 8 + static_cast<std::size_t>(header_len);
    if (data_len2 > n - data_pos) return Bad(where, "record data of " + std::to_string(data_len2) + " bytes runs past the chunk's end");
    if (std::string why = ParseFields(header, static_cast<std::size_t>(header_len), &inner_fields_); !why.empty()) {
      return Bad(where, why);
    }
    if (auto e = InnerRecord(where, inner_fields_, chunk + data_pos, static_cast<std::size_t>(data_len2))) return e;
    pos = data_pos + static_cast<std::size_t>(data_len2);
  }
  return std::nullopt;
}

std::optional<Error> Ros1Reader::InnerRecord(const BagPosition& where, const Fields& f, const std::uint8_t* data,
                                             std::size_t n) {
  std::uint64_t op = 0;
  if (!FieldInt(f, "op", 1, &op)) return Bad(where, "record without a 1-byte 'op' header field");
  if (op == kConnection) return Connection(where, f, data, n);
  if (op != kMessageData) return std::nullopt;
  std::uint64_t conn = 0, time = 0;
  if (!FieldInt(f, "conn", 4, &conn) || !FieldInt(f, "time", 8, &time)) {
    return Bad(where, "message data record without its 4-byte 'conn' and 8-byte 'time' fields");
  }
  if (connections_.count(conn) == 0) {
    return Bad(where, "message on connection " + std::to_string(conn) + ", which no connection record defined before it");
  }
  // "time": uint32 secs then uint32 nsecs.
  const std::uint64_t secs = time & 0xffffffffu, nsecs = time >> 32;
  if (nsecs >= 1000000000u) return Bad(where, "message time nsecs = " + std::to_string(nsecs) + " is not below 1e9");
  const std::uint64_t receive_ns = secs * 1000000000u + nsecs;
  visitor_->Count(conn, receive_ns);
  if (!visitor_->Wants(conn)) return std::nullopt;
  return visitor_->OnMessage(BagMessage{conn, receive_ns, data, n, where});
}

// The message count of every connection from the chunk info records of the index section. Only
// a hint: anything odd (no index, a record that does not parse) leaves the counts incomplete or
// empty, never an error: the sequential read checks every byte it uses. Each count is capped at
// the number of message records the file could hold (a hostile index cannot make a reader
// reserve more).
void Ros1Reader::ReadIndexCounts(const Fields& bag_header) {
  std::uint64_t index_pos = 0;
  const std::uint64_t size = bytes_.size();
  if (!FieldInt(bag_header, "index_pos", 8, &index_pos) || index_pos == 0 || index_pos >= size) return;
  std::vector<std::uint8_t> header_buf, data_buf;
  Fields f;
  for (std::uint64_t pos = index_pos; size - pos >= 8;) {
    const std::uint8_t* len = bytes_.View(pos, 4, &header_buf);
    if (len == nullptr) break;
    const std::uint64_t header_len = LoadLe(len, 4);
    if (header_len > size - pos - 4 || size - pos - 4 - header_len < 4 || header_len > options_.max_chunk_bytes) break;
    const std::uint8_t* header = bytes_.View(pos + 4, static_cast<std::size_t>(header_len) + 4, &header_buf);
    if (header == nullptr) break;
    const std::uint64_t data_len = LoadLe(header + header_len, 4);
    const std::uint64_t data_at = pos + 8 + header_len;
    std::uint64_t op = 0;
    if (data_len > size - data_at || !ParseFields(header, static_cast<std::size_t>(header_len), &f).empty() ||
        !FieldInt(f, "op", 1, &op)) {
      break;
    }
    if (op == kChunkInfo && data_len % 8 == 0 && data_len <= options_.max_chunk_bytes) {
      const std::uint8_t* d = bytes_.View(data_at, static_cast<std::size_t>(data_len), &data_buf);
      if (d == nullptr) break;
      for (std::uint64_t k = 0; k < data_len; k += 8) expected_[LoadLe(d + k, 4)] += LoadLe(d + k + 4, 4);
    }
    pos = data_at + data_len;
  }
  // A message data record is at least 8 length bytes and three fields (op, conn, time): 45 bytes.
  for (auto& [conn, count] : expected_) count = std::min<std::uint64_t>(count, size / 45);
}

std::optional<Error> Ros1Reader::Connection(const BagPosition& where, const Fields& f, const std::uint8_t* data,
                                            std::size_t n) {
  std::uint64_t conn = 0;
  const std::optional<std::string_view> topic = f.Find("topic");
  if (!FieldInt(f, "conn", 4, &conn) || !topic) {
    return Bad(where, "connection record without its 4-byte 'conn' and 'topic' fields");
  }
  Fields header;
  if (std::string why = ParseFields(data, n, &header); !why.empty()) return Bad(where, "connection header: " + why);
  if (!connections_.insert(conn).second) return std::nullopt;
  BagChannel ch;
  ch.id = conn;
  ch.topic = std::string(*topic);
  ch.type = std::string(header.Find("type").value_or(""));
  ch.encoding = "ros1";
  if (const auto it = expected_.find(conn); it != expected_.end()) ch.expected_messages = it->second;
  return visitor_->OnChannel(ch);
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
