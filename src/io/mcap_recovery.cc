// MCAP recovery (BagReadOptions::strict false); the reader's class is in mcap_reader.h.
// A Chunk whose uncompressed_crc does not match, that fails to decompress or whose records do not
// parse is skipped whole; the Message Index records after it count its messages lost per channel. A
// record whose opcode and length do not frame a record (its length runs past the file, the next
// record's header is not one either) is skipped to the next offset where a known opcode ("Opcodes")
// with a length inside the file is followed by another such record or the closing magic. The data
// section is read linearly, so a damaged summary only ends the read; the summary's Channel records
// are read only when a message's own Channel record was lost with a damaged chunk. After any damage
// the data section CRC is not checked (the damage already says the section is not the one written).
#include <algorithm>
#include <cstring>

#include "mcap_reader.h"

namespace gyrocomp::mcap_internal {

// "Records": a known opcode whose length fits in the file, followed by another such record or
// the closing magic (two records in a row: one byte pair rarely passes by chance).
bool McapReader::RecordStartsAt(std::uint64_t pos) {
  if (pos == size_) return true;
  std::vector<std::uint8_t> head;
  for (int k = 0; k < 2; ++k) {
    if (size_ - pos == kMagic.size() && k == 1) {
      return bag_internal::ReadAt(in_, pos, kMagic.size(), &head) && std::memcmp(head.data(), kMagic.data(), kMagic.size()) == 0;
    }
    if (size_ - pos < kRecordHeaderBytes || !bag_internal::ReadAt(in_, pos, kRecordHeaderBytes, &head)) return false;
    const std::uint64_t len = bag_internal::LoadLe(head.data() + 1, 8);
    if (!KnownOpcode(head[0]) || len > size_ - pos - kRecordHeaderBytes) return false;
    pos += kRecordHeaderBytes + len;
  }
  return true;
}

// Scans windows of 1 MiB for the first offset >= from where RecordStartsAt holds, or the file's size.
std::uint64_t McapReader::NextRecord(std::uint64_t from) {
  constexpr std::uint64_t kStep = std::uint64_t{1} << 20;
  std::vector<std::uint8_t> window;
  for (std::uint64_t base = from; base < size_; base += kStep) {
    const std::uint64_t avail = std::min<std::uint64_t>(size_ - base, kStep + kRecordHeaderBytes);
    if (!bag_internal::ReadAt(in_, base, static_cast<std::size_t>(avail), &window)) return size_;
    for (std::uint64_t k = 0; k < std::min<std::uint64_t>(avail, kStep); ++k) {
      // Cheap tests first: a known opcode and a length within the file.
      if (!KnownOpcode(window[k]) || avail - k < kRecordHeaderBytes) continue;
      const std::uint64_t len = bag_internal::LoadLe(window.data() + k + 1, 8);
      if (len > size_ - base - k - kRecordHeaderBytes) continue;
      if (RecordStartsAt(base + k)) return base + k;
    }
  }
  return size_;
}

// The range [d.begin, end) skipped. The Message Index records that follow count its messages
// lost (CloseLoss); the data section CRC is not checked any more.
void McapReader::AddDamage(const Damage& d, std::uint64_t end) {
  CloseLoss();
  damage_.emplace_back(d.begin, std::max(end, d.begin), d.what);
  crc_gap_ = true;
  if (data_end_) return;  // in the summary section: no message is lost
  loss_ = damage_.size() - 1;
  loss_told_ = false;
  delivered_ = chunk_delivered_;
  chunk_delivered_.clear();
}

// The damage being counted is complete; with no Message Index record after it, its loss cannot
// be told by channel.
void McapReader::CloseLoss() {
  if (loss_ && !loss_told_ && damage_[*loss_].end > damage_[*loss_].begin) damage_[*loss_].records_unidentified = 1;
  loss_.reset();
  delivered_.clear();
}

// "Summary Section": "The summary section contains schema, channel, chunk index, attachment
// index, metadata index, and statistics records"; "Footer": summary_start (0: no summary). The
// summary's Schema and Channel records repeat the data section's: a channel whose record was in
// a lost chunk is known from there. Recovery only (strict mode refuses the lost chunk first).
const BagChannel* McapReader::SummaryChannel(std::uint16_t channel) {
  if (options_.strict) return nullptr;
  if (!summary_channels_) ReadSummary();
  const auto it = summary_channels_->find(channel);
  return it == summary_channels_->end() ? nullptr : &it->second;
}

void McapReader::ReadSummary() {
  summary_channels_.emplace();
  const std::uint64_t footer_at = size_ - kMagic.size() - kRecordHeaderBytes - kFooterBytes;
  std::vector<std::uint8_t> footer;
  if (size_ < kMagic.size() * 2 + kRecordHeaderBytes + kFooterBytes ||
      !bag_internal::ReadAt(in_, footer_at, kRecordHeaderBytes + 8, &footer) || footer[0] != kFooter) {
    return;
  }
  std::map<std::uint16_t, std::string> schemas;
  std::vector<std::uint8_t> record;
  for (std::uint64_t pos = bag_internal::LoadLe(footer.data() + kRecordHeaderBytes, 8);
       pos >= kMagic.size() && pos < footer_at && footer_at - pos >= kRecordHeaderBytes;) {
    if (!bag_internal::ReadAt(in_, pos, kRecordHeaderBytes, &record)) return;
    const std::uint8_t op = record[0];
    const std::uint64_t len = bag_internal::LoadLe(record.data() + 1, 8);
    if (len > footer_at - pos - kRecordHeaderBytes) return;
    if ((op == kSchema || op == kChannel) && len <= kCrcReadBytes) {
      if (!bag_internal::ReadAt(in_, pos + kRecordHeaderBytes, static_cast<std::size_t>(len), &record)) return;
      Cursor c{record.data(), record.size()};
      std::uint64_t id = 0, schema = 0;
      BagChannel ch;
      std::string name;
      if (op == kSchema && c.Int(2, &id, "id") && c.Str(&name, "name")) schemas[static_cast<std::uint16_t>(id)] = name;
      if (op == kChannel && c.Int(2, &id, "id") && c.Int(2, &schema, "schema_id") && c.Str(&ch.topic, "topic") &&
          c.Str(&ch.encoding, "message_encoding")) {
        ch.id = id;
        if (const auto it = schemas.find(static_cast<std::uint16_t>(schema)); it != schemas.end()) ch.type = it->second;
        summary_channels_->emplace(static_cast<std::uint16_t>(id), std::move(ch));
      }
    }
    pos += kRecordHeaderBytes + len;
  }
}

std::string McapReader::TopicOf(std::uint16_t channel) const {
  const auto it = channels_.find(channel);
  return it != channels_.end() ? it->second : "channel " + std::to_string(channel);
}

}  // namespace gyrocomp::mcap_internal
