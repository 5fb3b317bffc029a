// MCAP reader (include/gyrocomp/io/bag.h): the data section streamed once, chunk by chunk
// (mcap_reader.h says how); recovery from damaged records in mcap_recovery.cc.
#include <algorithm>
#include <cstring>

#include "mcap_reader.h"

namespace gyrocomp {
namespace mcap_internal {

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
      if (auto e = EndWithoutFooter(pos)) return e;
      break;
    }
    std::optional<Damage> damage;
    std::uint64_t next = size_;
    if (auto e = TopRecord(pos, first, &next, &damage)) return e;
    first = false;
    if (damage) {
      if (options_.strict) return damage->positioned ? InvalidInput(source_ + ": " + damage->what) : Bad(damage->at, damage->what);
      // Each step moves forward: the resume point and the scan start are past `pos`.
      next = damage->resume && RecordStartsAt(*damage->resume) ? *damage->resume : NextRecord(damage->scan_from);
      AddDamage(*damage, next);
      // A damaged summary section: the data section was read whole, nothing after it is needed.
      if (data_end_) break;
    }
    pos = next;
  }
  CloseLoss();
  for (const auto& [key, count] : lost_) damage_[key.first].rows_lost[TopicOf(key.second)] += static_cast<std::size_t>(count);
  for (const LogDamage& d : damage_) visitor_->OnDamage(d);
  return std::nullopt;
}

// "File Structure": the file ends with <Footer><Magic>. Without them (an interrupted recording)
// strict mode refuses; recovery keeps what was read, noting it unless a damage already ran to the end.
std::optional<Error> McapReader::EndWithoutFooter(std::uint64_t pos) {
  const std::string why = "the file ends without the Footer record (\"File Structure\": ...<Footer><Magic>): "
                          "an interrupted recording? (`mcap recover` rewrites it)";
  if (options_.strict) return Bad(pos, why);
  if (damage_.empty() || damage_.back().end < size_) AddDamage(Damage{pos, why, pos, {}, pos, false}, pos);
  return std::nullopt;
}

// The record at `pos`: its opcode and length ("Records"), then its content (Record). Sets *next
// to the record after it, or *damage.
std::optional<Error> McapReader::TopRecord(std::uint64_t pos, bool first, std::uint64_t* next,
                                           std::optional<Damage>* damage) {
  if (size_ - pos < kRecordHeaderBytes) {
    *damage = Damage{pos, "truncated record: " + std::to_string(size_ - pos) + " of the 9 bytes of opcode and length", pos, {}, pos + 1, false};
    return std::nullopt;
  }
  std::vector<std::uint8_t> head;
  if (!bag_internal::ReadAt(in_, pos, kRecordHeaderBytes, &head)) return IoError(source_ + ": read error at byte " + std::to_string(pos));
  const std::uint8_t op = head[0];
  const std::uint64_t len = bag_internal::LoadLe(head.data() + 1, 8);
  const std::uint64_t body = pos + kRecordHeaderBytes;
  if (len > size_ - body) {
    *damage = Damage{pos, "record " + Hex(op) + " of " + std::to_string(len) + " bytes runs past the end of the file (" +
                              std::to_string(size_ - body) + " bytes left): truncated", pos, {}, pos + 1, false};
    return std::nullopt;
  }
  // "Header": "The first record after the leading magic is always a Header record."
  if (first && op != kHeader) {
    *damage = Damage{pos, "the first record is " + Hex(op) + ", not a Header (0x01)", pos, {}, pos + 1, false};
    return std::nullopt;
  }
  if (!data_end_ && op != kDataEnd) Crc(pos, head.data(), head.size());
  record_at_ = pos;
  record_end_ = *next = body + len;
  return Record(op, pos, len, damage);
}

std::optional<Error> McapReader::Record(std::uint8_t op, std::uint64_t at, std::uint64_t len,
                                        std::optional<Damage>* damage) {
  const std::uint64_t body = at + kRecordHeaderBytes;
  if (op == kFooter) return Footer(at, len, damage);
  // Summary section records (after Data End) repeat what the data section said: skipped.
  if (data_end_) return std::nullopt;
  switch (op) {
    case kDataEnd: return DataEnd(at, len, damage);
    case kSchema:
    case kChannel: {
      if (auto e = Body(at, len, op == kSchema ? "Schema" : "Channel", damage); e || *damage) return e;
      Crc(body, record_.data(), record_.size());
      std::string why;
      std::optional<Error> e;
      if (op == kSchema) Schema(record_.data(), record_.size(), &why);
      else e = Channel(record_.data(), record_.size(), &why);
      if (!why.empty()) *damage = Damage{at, why, at, body + len, at + 1, false};
      return e;
    }
    case kMessage: return DataMessage(at, len, damage);
    case kChunk: return Chunk(at, len, damage);
    case kMessageIndex: return MessageIndex(at, len);
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

// "Data End": uint32 data_section_crc (0: missing). Checked when every byte before it was read
// and nothing was skipped as damage.
std::optional<Error> McapReader::DataEnd(std::uint64_t at, std::uint64_t len, std::optional<Damage>* damage) {
  data_end_ = true;
  CloseLoss();
  if (len < 4) {
    *damage = Damage{at, "Data End record of " + std::to_string(len) + " bytes, needs 4", at, at + kRecordHeaderBytes + len, at + 1, false};
    return std::nullopt;
  }
  std::vector<std::uint8_t> field;
  if (!bag_internal::ReadAt(in_, at + kRecordHeaderBytes, 4, &field)) return IoError(source_ + ": read error at byte " + std::to_string(at));
  const auto declared = static_cast<std::uint32_t>(bag_internal::LoadLe(field.data(), 4));
  if (declared == 0 || crc_gap_ || crc_end_ != at || !damage_.empty() || crc_ == declared) return std::nullopt;
  const std::string why = "Data End: data section CRC mismatch: bytes 0-" + std::to_string(at) + " have CRC-32 " +
                          std::to_string(crc_) + ", the record declares " + std::to_string(declared) + " (corrupt data)";
  // A row read may hold the corrupt byte unless every message came from a chunk whose own CRC
  // matched: only then is the mismatch a damage listed (the Data End record) rather than an error.
  if (options_.strict || unverified_rows_) return Bad(at, why);
  *damage = Damage{at, why + "; every message came from a chunk whose own CRC matched", at,
                   at + kRecordHeaderBytes + len, at + 1, false};
  return std::nullopt;
}

// Reads a record's content into record_ (bounded by max_chunk_bytes).
std::optional<Error> McapReader::Body(std::uint64_t at, std::uint64_t len, const char* what, std::optional<Damage>* damage) {
  if (len > options_.max_chunk_bytes) {
    *damage = Damage{at, std::string(what) + " record of " + std::to_string(len) + " bytes exceeds the " +
                             std::to_string(options_.max_chunk_bytes) + "-byte limit (BagReadOptions::max_chunk_bytes)",
                     at, at + kRecordHeaderBytes + len, at + 1, false};
    return std::nullopt;
  }
  if (!bag_internal::ReadAt(in_, at + kRecordHeaderBytes, static_cast<std::size_t>(len), &record_)) {
    return IoError(source_ + ": read error at byte " + std::to_string(at));
  }
  return std::nullopt;
}

// "Schema": uint16 id, String name, String encoding, uint32-prefixed Bytes data.
// "A Schema record with id 0 is invalid" (id 0 means "no schema" in a Channel).
void McapReader::Schema(const std::uint8_t* p, std::size_t n, std::string* why) {
  Cursor c{p, n};
  std::uint64_t id = 0;
  std::string name, encoding;
  if (!c.Int(2, &id, "id") || !c.Str(&name, "name") || !c.Str(&encoding, "encoding")) {
    *why = "Schema record too short for its field '" + c.failed + "'";
  } else if (id == 0) {
    *why = "Schema with id 0 (reserved for \"no schema\")";
  } else {
    schema_names_[static_cast<std::uint16_t>(id)] = name;
  }
}

// "Channel": uint16 id, uint16 schema_id, String topic, String message_encoding,
// Map<string,string> metadata. "The schema_id ... must have been previously defined" (0: none).
std::optional<Error> McapReader::Channel(const std::uint8_t* p, std::size_t n, std::string* why) {
  Cursor c{p, n};
  std::uint64_t id = 0, schema = 0;
  BagChannel ch;
  if (!c.Int(2, &id, "id") || !c.Int(2, &schema, "schema_id") || !c.Str(&ch.topic, "topic") ||
      !c.Str(&ch.encoding, "message_encoding")) {
    *why = "Channel record too short for its field '" + c.failed + "'";
    return std::nullopt;
  }
  if (schema != 0) {
    const auto it = schema_names_.find(static_cast<std::uint16_t>(schema));
    if (it == schema_names_.end()) {
      *why = "Channel " + std::to_string(id) + " (" + ch.topic + ") refers to schema " + std::to_string(schema) +
             ", which no Schema record defined before it";
      return std::nullopt;
    }
    ch.type = it->second;
  }
  ch.id = id;
  // Channels may be repeated (in every chunk that uses them, and in the summary): announced once.
  if (!channels_.emplace(static_cast<std::uint16_t>(id), ch.topic).second) return std::nullopt;
  return visitor_->OnChannel(ch);
}

// A Message record's content in memory (in a chunk, or read from the data section).
std::optional<Error> McapReader::Message(const std::uint8_t* p, std::size_t n, const BagPosition& where, std::string* why) {
  if (n < kMessagePrefixBytes) {
    *why = "Message record of " + std::to_string(n) + " bytes, needs at least 22";
    return std::nullopt;
  }
  const auto channel = static_cast<std::uint16_t>(bag_internal::LoadLe(p, 2));
  const std::uint64_t log_time = bag_internal::LoadLe(p + 6, 8);
  if (const BagChannel* known = channels_.count(channel) ? nullptr : SummaryChannel(channel)) {
    channels_.emplace(channel, known->topic);
    if (auto e = visitor_->OnChannel(*known)) return e;
  }
  if (channels_.count(channel) == 0) {
    if (options_.strict) {
      *why = "Message on channel " + std::to_string(channel) + ", which no Channel record defined before it";
      return std::nullopt;
    }
    // Its Channel record was lost: one damage entry per such channel counts its messages.
    auto [d, added] = unknown_channel_damage_.emplace(channel, damage_.size());
    if (added) {
      damage_.emplace_back(record_at_, record_end_, "messages on channel " + std::to_string(channel) +
                                                        ", whose Channel record was lost");
    }
    damage_[d->second].end = record_end_;
    ++damage_[d->second].rows_lost["channel " + std::to_string(channel)];
    return std::nullopt;
  }
  if (where.chunk_byte) ++chunk_delivered_[channel];
  else unverified_rows_ = true;
  if (loss_) ++delivered_[channel];
  visitor_->Count(channel, log_time);
  if (!visitor_->Wants(channel)) return std::nullopt;
  BagMessage m{channel, log_time, p + kMessagePrefixBytes, n - kMessagePrefixBytes, where};
  return visitor_->OnMessage(m);
}

// A Message in the data section (unchunked files): the 22-byte prefix is read first, the data
// only when the channel is wanted.
std::optional<Error> McapReader::DataMessage(std::uint64_t at, std::uint64_t len, std::optional<Damage>* damage) {
  const BagPosition where{at, {}, {}};
  const std::uint64_t end = at + kRecordHeaderBytes + len;
  std::string why;
  std::optional<Error> e;
  if (len < kMessagePrefixBytes) {
    e = Message(nullptr, static_cast<std::size_t>(len), where, &why);
  } else {
    std::vector<std::uint8_t> prefix;
    if (!bag_internal::ReadAt(in_, at + kRecordHeaderBytes, kMessagePrefixBytes, &prefix)) {
      return IoError(source_ + ": read error at byte " + std::to_string(at));
    }
    Crc(at + kRecordHeaderBytes, prefix.data(), prefix.size());
    const auto channel = static_cast<std::uint16_t>(bag_internal::LoadLe(prefix.data(), 2));
    if (channels_.count(channel) && !visitor_->Wants(channel)) {
      if (loss_) ++delivered_[channel];
      visitor_->Count(channel, bag_internal::LoadLe(prefix.data() + 6, 8));
      return CrcSkipped(at + kRecordHeaderBytes + kMessagePrefixBytes, len - kMessagePrefixBytes);
    }
    if (auto b = Body(at, len, "Message", damage); b || *damage) return b;
    Crc(at + kRecordHeaderBytes, record_.data(), record_.size());
    e = Message(record_.data(), record_.size(), where, &why);
  }
  if (!why.empty()) *damage = Damage{at, why, at, end, at + 1, false};
  return e;
}

std::optional<Error> McapReader::Chunk(std::uint64_t at, std::uint64_t len, std::optional<Damage>* damage) {
  const std::uint64_t record_end = at + kRecordHeaderBytes + len;
  chunk_delivered_.clear();
  last_chunk_.clear();
  // A chunk that cannot be read is skipped whole (its messages lost); reading goes on after it
  // when a record starts there, else at the next record after its opcode.
  const auto lost = [&](const std::string& what) {
    *damage = Damage{at, what, at, record_end, at + 1, false};
    return std::nullopt;
  };
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
    return lost("Chunk record too short for its field '" + c.failed + "'");
  }
  const std::uint64_t records_at = at + kRecordHeaderBytes + c.pos;
  // "Records": a record may be longer than its known fields (fields added by later versions):
  // the records must fit in it, anything after them is skipped.
  if (records_len > len - c.pos) {
    return lost("Chunk records length " + std::to_string(records_len) + " runs past the record (" +
                std::to_string(len - c.pos) + " bytes after the chunk's fields)");
  }
  // "Chunk": compression "" (none), "lz4", "zstd" (the values the spec lists as supported).
  if (compression != "" && compression != "zstd" && compression != "lz4") {
    return lost("Chunk compression '" + compression + "' is not one MCAP defines (\"\", \"lz4\", \"zstd\")");
  }
  // The declared uncompressed size bounds every allocation (compression bombs).
  if (usize > options_.max_chunk_bytes || records_len > options_.max_chunk_bytes) {
    return lost("Chunk declares " + std::to_string(usize) + " uncompressed bytes (" + std::to_string(records_len) +
                " compressed): more than the " + std::to_string(options_.max_chunk_bytes) +
                "-byte limit (BagReadOptions::max_chunk_bytes); refused as a possible compression bomb");
  }
  if (compression.empty() && usize != records_len) {
    return lost("uncompressed Chunk declares " + std::to_string(usize) + " bytes but holds " + std::to_string(records_len));
  }
  std::vector<std::uint8_t>& target = compression.empty() ? chunk_ : compressed_;
  if (!bag_internal::ReadAt(in_, records_at, static_cast<std::size_t>(records_len), &target)) {
    return IoError(source_ + ": read error at byte " + std::to_string(records_at));
  }
  Crc(records_at, target.data(), target.size());
  // Bytes after the records (fields of a later version) are not needed but go into the CRC.
  if (!crc_gap_ && crc_end_ < record_end) {
    if (auto e = CrcSkipped(crc_end_, record_end - crc_end_)) return e;
  }
  if (!compression.empty()) {
    chunk_.assign(static_cast<std::size_t>(usize), 0);
    const std::string why = bag_internal::Decompress(compression, compressed_.data(), compressed_.size(), &chunk_);
    if (!why.empty()) return lost("Chunk: " + why);
  }
  // "uncompressed_crc: CRC32 checksum of the uncompressed records field. A value of zero
  // indicates that CRC validation should not be performed."
  if (crc == 0) unverified_rows_ = true;
  if (crc != 0) {
    const std::uint32_t got = bag_internal::Crc32(chunk_.data(), chunk_.size());
    if (got != crc) {
      return lost("Chunk CRC mismatch: the records' CRC-32 is " + std::to_string(got) + ", the chunk declares " +
                  std::to_string(crc) + " (corrupt data)");
    }
  }
  if (auto e = ChunkRecords(at, damage); e || *damage) return e;
  // An intact chunk: the Message Index records after it are its own.
  CloseLoss();
  last_chunk_ = std::move(chunk_delivered_);
  chunk_delivered_.clear();
  return std::nullopt;
}

// The records inside a chunk: Schema, Channel and Message ("Chunk": "...may contain Schema,
// Channel and Message records"); anything else is skipped like an unknown record. A record that
// cannot be read loses the rest of the chunk.
std::optional<Error> McapReader::ChunkRecords(std::uint64_t at, std::optional<Damage>* damage) {
  const std::size_t n = chunk_.size();
  std::size_t pos = 0;
  std::string why;
  while (pos < n && why.empty()) {
    const BagPosition where{at, pos, {}};
    if (n - pos < kRecordHeaderBytes) {
      why = "truncated record inside the chunk (" + std::to_string(n - pos) + " of the 9 bytes of opcode and length)";
      break;
    }
    const std::uint8_t op = chunk_[pos];
    const std::uint64_t len = bag_internal::LoadLe(chunk_.data() + pos + 1, 8);
    const std::size_t body = pos + kRecordHeaderBytes;
    if (len > n - body) {
      why = "record " + Hex(op) + " of " + std::to_string(len) + " bytes runs past the chunk's end (" +
            std::to_string(n - body) + " bytes left)";
      break;
    }
    const std::uint8_t* p = chunk_.data() + body;
    const auto l = static_cast<std::size_t>(len);
    std::optional<Error> e;
    if (op == kSchema) Schema(p, l, &why);
    else if (op == kChannel) e = Channel(p, l, &why);
    else if (op == kMessage) e = Message(p, l, where, &why);
    if (e) return e;
    if (why.empty()) pos = body + l;
  }
  if (!why.empty()) {
    *damage = Damage{at, BagPosition{at, pos, {}}.ToString() + ": " + why, at, record_end_, at + 1, true};
  }
  return std::nullopt;
}

// "Message Index": uint16 channel_id, then (Timestamp log_time, uint64 offset) pairs with a
// uint32 byte length: one per message of that channel in the chunk before it. After a damaged
// chunk they are the messages it lost.
std::optional<Error> McapReader::MessageIndex(std::uint64_t at, std::uint64_t len) {
  if (auto e = CrcSkipped(at + kRecordHeaderBytes, len)) return e;
  if (len < 6) return std::nullopt;
  std::vector<std::uint8_t> head;
  if (!bag_internal::ReadAt(in_, at + kRecordHeaderBytes, 6, &head)) return IoError(source_ + ": read error at byte " + std::to_string(at));
  const auto channel = static_cast<std::uint16_t>(bag_internal::LoadLe(head.data(), 2));
  if (!loss_) {
    last_chunk_.erase(channel);  // seen: a later index of this channel is another chunk's
    return std::nullopt;
  }
  const std::uint64_t bytes = std::min<std::uint64_t>(bag_internal::LoadLe(head.data() + 2, 4), len - 6);
  const std::uint64_t count = bytes / 16;
  // The last intact chunk's own index (the damage hit one of its Message Index records).
  if (const auto it = last_chunk_.find(channel); it != last_chunk_.end() && it->second == count) {
    last_chunk_.erase(it);
    return std::nullopt;
  }
  last_chunk_.clear();
  loss_told_ = true;
  std::uint64_t& got = delivered_[channel];
  const std::uint64_t read = std::min(got, count);
  got -= read;
  if (count > read) lost_[{*loss_, channel}] += count - read;
  return std::nullopt;
}

// "Footer" then the closing magic, which must end the file.
std::optional<Error> McapReader::Footer(std::uint64_t at, std::uint64_t len, std::optional<Damage>* damage) {
  CloseLoss();
  if (len < kFooterBytes) {
    *damage = Damage{at, "Footer record of " + std::to_string(len) + " bytes, needs 20", at, {}, at + 1, false};
    return std::nullopt;
  }
  const std::uint64_t magic_at = at + kRecordHeaderBytes + len;
  if (size_ - magic_at != kMagic.size() || !bag_internal::ReadAt(in_, magic_at, kMagic.size(), &record_) ||
      std::memcmp(record_.data(), kMagic.data(), kMagic.size()) != 0) {
    *damage = Damage{magic_at, "the Footer is not followed by the closing magic at the end of the file", magic_at, size_, size_, false};
    return std::nullopt;
  }
  done_ = true;
  return std::nullopt;
}

}  // namespace mcap_internal

std::optional<Error> StreamMcap(std::istream& in, const std::string& source, const BagReadOptions& options,
                                BagVisitor* visitor) {
  mcap_internal::McapReader reader(in, source, options, visitor);
  return reader.Run();
}

}  // namespace gyrocomp
