// MCAP reader (include/gyrocomp/io/bag.h), written from the MCAP specification, version 0
// ("MCAP Format Specification", mcap.dev/spec, foxglove/mcap docs/specification/README.md).
// Quotes below are its section names.
//
// "File Structure": <Magic><Header><Data section>[<Summary section>][<Summary Offset section>]
//   <Footer><Magic>. "Magic": 0x89 M C A P 0x30 \r \n (8 bytes, the '0' is the major version).
// "Records": opcode uint8, length uint64 (little-endian, like every integer), content. Readers
//   skip records with unknown opcodes ("Opcodes 0x80-0xFF are reserved ... readers should ignore
//   unknown records"). "Serialization": String = uint32 length + UTF-8 bytes; Bytes in a Schema
//   = uint32 length + bytes; Timestamp = uint64 nanoseconds.
// This reader streams the data section once: Schema and Channel records are kept (a Channel
// names its topic and message encoding, its Schema the type), Message records of channels the
// consumer does not want are skipped without being read, Chunks are decompressed one at a time
// and only their wanted messages are passed on. The summary section is optional and not needed:
// after "Data End" the records are skipped up to the Footer. Chunk CRCs are checked.
// "Data End": "data_section_crc: CRC-32 of all bytes in the data section. A value of zero
// indicates the CRC is missing." The data section runs from the leading magic (byte 0) to the
// Data End record (excluded), as foxglove/mcap's python StreamReader computes it. Every byte
// this reader reads in that range, in file order, goes into a running CRC-32; the CRC is checked
// when no byte was left unread: chunks (rosbag2 chunks every message) and Schema / Channel
// records are read whole anyway, and records otherwise skipped (message indexes, metadata,
// unknown records, messages of unwanted channels outside chunks) are read for the CRC when they
// are at most kCrcReadBytes; a larger one is skipped unread and the CRC left unchecked, unless
// BagReadOptions::verify_mcap_data_crc asks for every byte to be read.
#include <algorithm>
#include <array>
#include <cstring>
#include <map>
#include <set>

#include "bag_bytes.h"
#include "gyrocomp/io/bag.h"

namespace gyrocomp {

namespace {

using bag_internal::Cursor;

constexpr std::array<std::uint8_t, 8> kMagic = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr std::size_t kRecordHeaderBytes = 9;  // "Records": uint8 opcode + uint64 length

// "Opcodes" table.
enum Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kDataEnd = 0x0F,
};
// "Footer": uint64 summary_start, uint64 summary_offset_start, uint32 summary_crc.
constexpr std::uint64_t kFooterBytes = 20;
// "Message": uint16 channel_id, uint32 sequence, Timestamp log_time, Timestamp publish_time,
// then the message data up to the record's end.
constexpr std::size_t kMessagePrefixBytes = 2 + 4 + 8 + 8;
// "Chunk": Timestamp message_start_time, Timestamp message_end_time, uint64 uncompressed_size,
// uint32 uncompressed_crc, String compression, uint64-prefixed Bytes records.
constexpr std::size_t kChunkFixedBytes = 8 + 8 + 8 + 4;
// Records the reader would skip are still read, for the data section CRC, up to this size.
constexpr std::uint64_t kCrcReadBytes = std::uint64_t{1} << 20;

std::string Hex(unsigned v) {
  static const char* d = "0123456789abcdef";
  return std::string("0x") + d[(v >> 4) & 15] + d[v & 15];
}

class McapReader {
 public:
  McapReader(std::istream& in, const std::string& source, const BagReadOptions& options, BagVisitor* visitor)
      : in_(in), source_(source), options_(options), visitor_(visitor) {}
  std::optional<Error> Run();

 private:
  Error Bad(std::uint64_t offset, const std::string& what) const {
    return InvalidInput(source_ + ": byte " + std::to_string(offset) + ": " + what);
  }
  std::optional<Error> Record(std::uint8_t op, std::uint64_t at, std::uint64_t len);
  std::optional<Error> Body(std::uint64_t at, std::uint64_t len, const char* what);
  std::optional<Error> Schema(const std::uint8_t* p, std::size_t n, const BagPosition& where);
  std::optional<Error> Channel(const std::uint8_t* p, std::size_t n, const BagPosition& where);
  std::optional<Error> Message(const std::uint8_t* p, std::size_t n, const BagPosition& where);
  std::optional<Error> DataMessage(std::uint64_t at, std::uint64_t len);
  std::optional<Error> Chunk(std::uint64_t at, std::uint64_t len);
  std::optional<Error> ChunkRecords(std::uint64_t at);
  std::optional<Error> Footer(std::uint64_t at, std::uint64_t len);
  std::optional<Error> DataEnd(std::uint64_t at, std::uint64_t len);
  // Feeds bytes [at, at + n) of the file, just read, into the data section CRC.
  void Crc(std::uint64_t at, const std::uint8_t* p, std::size_t n);
  // Reads bytes [at, at + n) that the reader itself does not need, for the CRC only.
  std::optional<Error> CrcSkipped(std::uint64_t at, std::uint64_t n);

  std::istream& in_;
  const std::string& source_;
  const BagReadOptions& options_;
  BagVisitor* visitor_;
  std::uint64_t size_ = 0;
  bool data_end_ = false;
  bool done_ = false;
  std::uint32_t crc_ = 0;       // CRC-32 of bytes [0, crc_end_)
  std::uint64_t crc_end_ = 0;
  bool crc_gap_ = false;        // a byte of the data section was not read
  std::map<std::uint16_t, std::string> schema_names_;   // "Schema": id -> name
  std::set<std::uint16_t> channels_;                    // channel ids announced
  std::vector<std::uint8_t> record_, compressed_, chunk_;
};

std::optional<Error> McapReader::Run() {
  const std::int64_t size = bag_internal::StreamSize(in_);
  if (size < 0) return IoError(source_ + ": cannot read (not seekable)");
  size_ = static_cast<std::uint64_t>(size);
  if (size_ < kMagic.size() || !bag_internal::ReadAt(in_, 0, kMagic.size(), &record_) ||
      std::memcmp(record_.data(), kMagic.data(), kMagic.size()) != 0) {
    return Bad(0, "not an MCAP file (\"Magic\": 89 4D 43 41 50 30 0D 0A)");
  }
  Crc(0, record_.data(), record_.size());
  std::uint64_t pos = kMagic.size();
  bool first = true;
  while (!done_) {
    if (pos == size_) {
      return Bad(pos, "the file ends without the Footer record (\"File Structure\": ...<Footer><Magic>): "
                      "an interrupted recording? (`mcap recover` rewrites it)");
    }
    if (size_ - pos < kRecordHeaderBytes) {
      return Bad(pos, "truncated record: " + std::to_string(size_ - pos) + " of the 9 bytes of opcode and length");
    }
    std::vector<std::uint8_t> head;
    if (!bag_internal::ReadAt(in_, pos, kRecordHeaderBytes, &head)) return IoError(source_ + ": read error at byte " + std::to_string(pos));
    const std::uint8_t op = head[0];
    if (!data_end_ && op != kDataEnd) Crc(pos, head.data(), head.size());
    const std::uint64_t len = bag_internal::LoadLe(head.data() + 1, 8);
    const std::uint64_t body = pos + kRecordHeaderBytes;
    if (len > size_ - body) {
      return Bad(pos, "record " + Hex(op) + " of " + std::to_string(len) + " bytes runs past the end of the file (" +
                          std::to_string(size_ - body) + " bytes left): truncated");
    }
    // "Header": "The first record after the leading magic is always a Header record."
    if (first && op != kHeader) return Bad(pos, "the first record is " + Hex(op) + ", not a Header (0x01)");
    first = false;
    if (auto e = Record(op, pos, len)) return e;
    pos = body + len;
  }
  return std::nullopt;
}

std::optional<Error> McapReader::Record(std::uint8_t op, std::uint64_t at, std::uint64_t len) {
  const std::uint64_t body = at + kRecordHeaderBytes;
  if (op == kFooter) return Footer(at, len);
  // Summary section records (after Data End) repeat what the data section said: skipped.
  if (data_end_) return std::nullopt;
  switch (op) {
    case kDataEnd: return DataEnd(at, len);
    case kSchema:
    case kChannel: {
      if (auto e = Body(at, len, op == kSchema ? "Schema" : "Channel")) return e;
      Crc(body, record_.data(), record_.size());
      const BagPosition where{at, {}, {}};
      return op == kSchema ? Schema(record_.data(), record_.size(), where) : Channel(record_.data(), record_.size(), where);
    }
    case kMessage: return DataMessage(at, len);
    case kChunk: return Chunk(at, len);
    default: return CrcSkipped(body, len);  // Header, indexes, attachments, metadata, unknown
  }
}

void McapReader::Crc(std::uint64_t at, const std::uint8_t* p, std::size_t n) {
  if (crc_gap_ || at > crc_end_) {
    crc_gap_ = true;
    return;
  }
  const std::uint64_t skip = crc_end_ - at;  // bytes already in the CRC (a record read again)
  if (skip >= n) return;
  crc_ = bag_internal::Crc32Update(crc_, p + skip, n - static_cast<std::size_t>(skip));
  crc_end_ = at + n;
}

std::optional<Error> McapReader::CrcSkipped(std::uint64_t at, std::uint64_t n) {
  if (crc_gap_ || n == 0) return std::nullopt;
  if (n > kCrcReadBytes && !options_.verify_mcap_data_crc) {
    crc_gap_ = true;
    return std::nullopt;
  }
  std::vector<std::uint8_t> piece;
  for (std::uint64_t done = 0; done < n;) {
    const auto k = static_cast<std::size_t>(std::min<std::uint64_t>(n - done, kCrcReadBytes));
    if (!bag_internal::ReadAt(in_, at + done, k, &piece)) return IoError(source_ + ": read error at byte " + std::to_string(at + done));
    Crc(at + done, piece.data(), k);
    done += k;
  }
  return std::nullopt;
}

// "Data End": uint32 data_section_crc (0: missing). Checked when every byte before it was read.
std::optional<Error> McapReader::DataEnd(std::uint64_t at, std::uint64_t len) {
  data_end_ = true;
  if (len < 4) return Bad(at, "Data End record of " + std::to_string(len) + " bytes, needs 4");
  std::vector<std::uint8_t> field;
  if (!bag_internal::ReadAt(in_, at + kRecordHeaderBytes, 4, &field)) return IoError(source_ + ": read error at byte " + std::to_string(at));
  const auto declared = static_cast<std::uint32_t>(bag_internal::LoadLe(field.data(), 4));
  if (declared == 0 || crc_gap_ || crc_end_ != at) return std::nullopt;
  if (crc_ != declared) {
    return Bad(at, "Data End: data section CRC mismatch: bytes 0-" + std::to_string(at) + " have CRC-32 " +
                       std::to_string(crc_) + ", the record declares " + std::to_string(declared) + " (corrupt data)");
  }
  return std::nullopt;
}

// Reads a record's content into record_ (bounded by max_chunk_bytes).
std::optional<Error> McapReader::Body(std::uint64_t at, std::uint64_t len, const char* what) {
  if (len > options_.max_chunk_bytes) {
    return Bad(at, std::string(what) + " record of " + std::to_string(len) + " bytes exceeds the " +
                       std::to_string(options_.max_chunk_bytes) + "-byte limit (BagReadOptions::max_chunk_bytes)");
  }
  if (!bag_internal::ReadAt(in_, at + kRecordHeaderBytes, static_cast<std::size_t>(len), &record_)) {
    return IoError(source_ + ": read error at byte " + std::to_string(at));
  }
  return std::nullopt;
}

// "Schema": uint16 id, String name, String encoding, uint32-prefixed Bytes data.
// "A Schema record with id 0 is invalid" (id 0 means "no schema" in a Channel).
std::optional<Error> McapReader::Schema(const std::uint8_t* p, std::size_t n, const BagPosition& where) {
  Cursor c{p, n};
  std::uint64_t id = 0;
  std::string name, encoding;
  if (!c.Int(2, &id, "id") || !c.Str(&name, "name") || !c.Str(&encoding, "encoding")) {
    return InvalidInput(source_ + ": " + where.ToString() + ": Schema record too short for its field '" + c.failed + "'");
  }
  if (id == 0) return InvalidInput(source_ + ": " + where.ToString() + ": Schema with id 0 (reserved for \"no schema\")");
  schema_names_[static_cast<std::uint16_t>(id)] = name;
  return std::nullopt;
}

// "Channel": uint16 id, uint16 schema_id, String topic, String message_encoding,
// Map<string,string> metadata. "The schema_id ... must have been previously defined" (0: none).
std::optional<Error> McapReader::Channel(const std::uint8_t* p, std::size_t n, const BagPosition& where) {
  Cursor c{p, n};
  std::uint64_t id = 0, schema = 0;
  BagChannel ch;
  if (!c.Int(2, &id, "id") || !c.Int(2, &schema, "schema_id") || !c.Str(&ch.topic, "topic") ||
      !c.Str(&ch.encoding, "message_encoding")) {
    return InvalidInput(source_ + ": " + where.ToString() + ": Channel record too short for its field '" + c.failed + "'");
  }
  if (schema != 0) {
    const auto it = schema_names_.find(static_cast<std::uint16_t>(schema));
    if (it == schema_names_.end()) {
      return InvalidInput(source_ + ": " + where.ToString() + ": Channel " + std::to_string(id) + " (" + ch.topic +
                          ") refers to schema " + std::to_string(schema) + ", which no Schema record defined before it");
    }
    ch.type = it->second;
  }
  ch.id = id;
  // Channels may be repeated (in every chunk that uses them, and in the summary): announced once.
  if (!channels_.insert(static_cast<std::uint16_t>(id)).second) return std::nullopt;
  return visitor_->OnChannel(ch);
}

// A Message record's content in memory (in a chunk, or read from the data section).
std::optional<Error> McapReader::Message(const std::uint8_t* p, std::size_t n, const BagPosition& where) {
  if (n < kMessagePrefixBytes) {
    return InvalidInput(source_ + ": " + where.ToString() + ": Message record of " + std::to_string(n) + " bytes, needs at least 22");
  }
  const auto channel = static_cast<std::uint16_t>(bag_internal::LoadLe(p, 2));
  const std::uint64_t log_time = bag_internal::LoadLe(p + 6, 8);
  if (channels_.count(channel) == 0) {
    return InvalidInput(source_ + ": " + where.ToString() + ": Message on channel " + std::to_string(channel) +
                        ", which no Channel record defined before it");
  }
  visitor_->Count(channel, log_time);
  if (!visitor_->Wants(channel)) return std::nullopt;
  BagMessage m{channel, log_time, p + kMessagePrefixBytes, n - kMessagePrefixBytes, where};
  return visitor_->OnMessage(m);
}

// A Message in the data section (unchunked files): the 22-byte prefix is read first, the data
// only when the channel is wanted.
std::optional<Error> McapReader::DataMessage(std::uint64_t at, std::uint64_t len) {
  const BagPosition where{at, {}, {}};
  if (len < kMessagePrefixBytes) return Message(nullptr, static_cast<std::size_t>(len), where);
  std::vector<std::uint8_t> prefix;
  if (!bag_internal::ReadAt(in_, at + kRecordHeaderBytes, kMessagePrefixBytes, &prefix)) {
    return IoError(source_ + ": read error at byte " + std::to_string(at));
  }
  Crc(at + kRecordHeaderBytes, prefix.data(), prefix.size());
  const auto channel = static_cast<std::uint16_t>(bag_internal::LoadLe(prefix.data(), 2));
  if (channels_.count(channel) && !visitor_->Wants(channel)) {
    visitor_->Count(channel, bag_internal::LoadLe(prefix.data() + 6, 8));
    return CrcSkipped(at + kRecordHeaderBytes + kMessagePrefixBytes, len - kMessagePrefixBytes);
  }
  if (auto e = Body(at, len, "Message")) return e;
  Crc(at + kRecordHeaderBytes, record_.data(), record_.size());
  return Message(record_.data(), record_.size(), where);
}

std::optional<Error> McapReader::Chunk(std::uint64_t at, std::uint64_t len) {
  // Fixed fields and the compression string first (small), then the records.
  std::vector<std::uint8_t> head;
  const std::size_t head_len = static_cast<std::size_t>(std::min<std::uint64_t>(len, kChunkFixedBytes + 4 + 256 + 8));
  if (!bag_internal::ReadAt(in_, at + kRecordHeaderBytes, head_len, &head)) {
    return IoError(source_ + ": read error at byte " + std::to_string(at));
  }
  Crc(at + kRecordHeaderBytes, head.data(), head.size());
  Cursor c{head.data(), head.size()};
  std::uint64_t start = 0, end = 0, usize = 0, crc = 0, records_len = 0;
  std::string compression;
  if (!c.Int(8, &start, "message_start_time") || !c.Int(8, &end, "message_end_time") ||
      !c.Int(8, &usize, "uncompressed_size") || !c.Int(4, &crc, "uncompressed_crc") ||
      !c.Str(&compression, "compression") || !c.Int(8, &records_len, "records length")) {
    return Bad(at, "Chunk record too short for its field '" + c.failed + "'");
  }
  const std::uint64_t records_at = at + kRecordHeaderBytes + c.pos;
  // "Records": a record may be longer than its known fields (fields added by later versions):
  // the records must fit in it, anything after them is skipped.
  if (records_len > len - c.pos) {
    return Bad(at, "Chunk records length " + std::to_string(records_len) + " runs past the record (" +
                       std::to_string(len - c.pos) + " bytes after the chunk's fields)");
  }
  // "Chunk": compression "" (none), "lz4", "zstd" (the values the spec lists as supported).
  if (compression != "" && compression != "zstd" && compression != "lz4") {
    return Bad(at, "Chunk compression '" + compression + "' is not one MCAP defines (\"\", \"lz4\", \"zstd\")");
  }
  // The declared uncompressed size bounds every allocation (compression bombs).
  if (usize > options_.max_chunk_bytes || records_len > options_.max_chunk_bytes) {
    return Bad(at, "Chunk declares " + std::to_string(usize) + " uncompressed bytes (" + std::to_string(records_len) +
                       " compressed): more than the " + std::to_string(options_.max_chunk_bytes) +
                       "-byte limit (BagReadOptions::max_chunk_bytes); refused as a possible compression bomb");
  }
  if (compression.empty() && usize != records_len) {
    return Bad(at, "uncompressed Chunk declares " + std::to_string(usize) + " bytes but holds " + std::to_string(records_len));
  }
  std::vector<std::uint8_t>& target = compression.empty() ? chunk_ : compressed_;
  if (!bag_internal::ReadAt(in_, records_at, static_cast<std::size_t>(records_len), &target)) {
    return IoError(source_ + ": read error at byte " + std::to_string(records_at));
  }
  Crc(records_at, target.data(), target.size());
  // Bytes after the records (fields of a later version) are not needed but go into the CRC.
  const std::uint64_t record_end = at + kRecordHeaderBytes + len;
  if (!crc_gap_ && crc_end_ < record_end) {
    if (auto e = CrcSkipped(crc_end_, record_end - crc_end_)) return e;
  }
  if (!compression.empty()) {
    chunk_.assign(static_cast<std::size_t>(usize), 0);
    const std::string why = bag_internal::Decompress(compression, compressed_.data(), compressed_.size(), &chunk_);
    if (!why.empty()) return Bad(at, "Chunk: " + why);
  }
  // "uncompressed_crc: CRC32 checksum of the uncompressed records field. A value of zero
  // indicates that CRC validation should not be performed."
  if (crc != 0) {
    const std::uint32_t got = bag_internal::Crc32(chunk_.data(), chunk_.size());
    if (got != crc) {
      return Bad(at, "Chunk CRC mismatch: the records' CRC-32 is " + std::to_string(got) + ", the chunk declares " +
                         std::to_string(crc) + " (corrupt data)");
    }
  }
  return ChunkRecords(at);
}

// The records inside a chunk: Schema, Channel and Message ("Chunk": "...may contain Schema,
// Channel and Message records"); anything else is skipped like an unknown record.
std::optional<Error> McapReader::ChunkRecords(std::uint64_t at) {
  const std::size_t n = chunk_.size();
  std::size_t pos = 0;
  while (pos < n) {
    const BagPosition where{at, pos, {}};
    if (n - pos < kRecordHeaderBytes) {
      return InvalidInput(source_ + ": " + where.ToString() + ": truncated record inside the chunk (" + std::to_string(n - pos) +
                          " of the 9 bytes of opcode and length)");
    }
    const std::uint8_t op = chunk_[pos];
    const std::uint64_t len = bag_internal::LoadLe(chunk_.data() + pos + 1, 8);
    const std::size_t body = pos + kRecordHeaderBytes;
    if (len > n - body) {
      return InvalidInput(source_ + ": " + where.ToString() + ": record " + Hex(op) + " of " + std::to_string(len) +
                          " bytes runs past the chunk's end (" + std::to_string(n - body) + " bytes left)");
    }
    const std::uint8_t* p = chunk_.data() + body;
    const auto l = static_cast<std::size_t>(len);
    std::optional<Error> e;
    if (op == kSchema) e = Schema(p, l, where);
    else if (op == kChannel) e = Channel(p, l, where);
    else if (op == kMessage) e = Message(p, l, where);
    if (e) return e;
    pos = body + l;
  }
  return std::nullopt;
}

// "Footer" then the closing magic, which must end the file.
std::optional<Error> McapReader::Footer(std::uint64_t at, std::uint64_t len) {
  if (len < kFooterBytes) return Bad(at, "Footer record of " + std::to_string(len) + " bytes, needs 20");
  const std::uint64_t magic_at = at + kRecordHeaderBytes + len;
  if (size_ - magic_at != kMagic.size() || !bag_internal::ReadAt(in_, magic_at, kMagic.size(), &record_) ||
      std::memcmp(record_.data(), kMagic.data(), kMagic.size()) != 0) {
    return Bad(magic_at, "the Footer is not followed by the closing magic at the end of the file");
  }
  done_ = true;
  return std::nullopt;
}

}  // namespace

std::optional<Error> StreamMcap(std::istream& in, const std::string& source, const BagReadOptions& options,
                                BagVisitor* visitor) {
  McapReader reader(in, source, options, visitor);
  return reader.Run();
}

}  // namespace gyrocomp
