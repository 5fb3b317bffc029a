// ROS 1 bag recovery (BagReadOptions::strict false); the reader's class is in rosbag1_reader.h.
// A record whose header_len, header fields or data_len do not frame a record is skipped to the next
// offset where a record header parses, names a record kind ("op") with the fields that kind
// requires, and declares data within the file. A chunk that fails to decompress (bz2, lz4) or whose
// records do not parse loses its own messages and reading goes on after its data (or at the next
// record, when its data length was the damage); an uncompressed chunk's records are the file's
// bytes, so reading goes on at the next record inside it. The index section ("Chunk info":
// chunk_pos and messages per connection; "Connection") tells the messages a lost chunk held per
// topic, and the topic of a connection whose record was in a lost chunk.
#include <algorithm>
#include <cstring>

#include "rosbag1_reader.h"

namespace gyrocomp::ros1_internal {

namespace {

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

}  // namespace

bool RecordStartsAt(const std::uint8_t* p, std::uint64_t avail, std::uint64_t left, Fields* scratch) {
  if (avail < 8) return false;
  const std::uint64_t header_len = LoadLe(p, 4);
  // The shortest header is one field "op=X": 4 length bytes + 4 bytes.
  if (header_len < 8 || header_len > kMaxResyncHeader || header_len + 8 > avail) return false;
  const std::uint64_t data_len = LoadLe(p + 4 + header_len, 4);
  if (data_len > left - 8 - header_len) return false;
  return ParseFields(p + 4, static_cast<std::size_t>(header_len), scratch).empty() && IsResyncRecord(*scratch);
}

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

}  // namespace gyrocomp::ros1_internal
