// ULog recovery (ULogReadOptions::strict false): how the parser tells an intact record from a
// damaged one. ULog records carry no checksum, so a record is decoded only when what follows it
// is itself a record this reader would accept (spec "Data Section": records follow each other
// with no gap); a size damaged into the next record, or a record cut short, would otherwise make
// a row out of bytes from two records. Checks are strict: a 'D' must name a subscribed msg_id
// (or the one its 'A' just introduced) with a size its format allows, keys must be printable.
#include "ulog_parser.h"

#include <algorithm>

#include "gyrocomp/io/log_damage.h"

namespace gyrocomp::ulog_detail {

namespace {

// spec "Information Message" etc.: a key is "<type> <name>", printable ASCII.
bool PrintableKey(const std::uint8_t* key, std::size_t len) {
  bool space = false;
  for (std::size_t i = 0; i < len; ++i) {
    if (key[i] < 0x20 || key[i] > 0x7e) return false;
    space = space || key[i] == ' ';
  }
  return space;
}

}  // namespace

Introduced Parser::IntroducedBy(std::size_t at) const {
  Introduced out;
  const std::size_t len = U16(d_ + at);
  const std::uint8_t* p = d_ + at + kMessageHeaderBytes;
  const char type = static_cast<char>(d_[at + 2]);
  if (type == 'A' && len >= 4) out.msg_id = U16(p + 1);  // uint8 multi_id, uint16 msg_id, name
  if (type == 'F') {
    const std::string_view f(reinterpret_cast<const char*>(p), len);
    out.format = std::string(f.substr(0, f.find(':')));
  }
  return out;
}

bool Parser::PlausibleAt(std::size_t at, std::size_t end, const Introduced& prev, bool allow_cut) const {
  if (at >= end || end - at < kMessageHeaderBytes) return false;
  const std::size_t len = U16(d_ + at);
  const char type = static_cast<char>(d_[at + 2]);
  if (!KnownType(type)) return false;
  // A record cut by the end of the segment is checked on the bytes it has.
  const std::size_t avail = std::min(len, end - at - kMessageHeaderBytes);
  if (avail < len && !allow_cut) return false;
  const std::uint8_t* p = d_ + at + kMessageHeaderBytes;
  switch (type) {
    case 'B': return false;  // only ever the first message
    case 'S': return len == sizeof kSyncMagic && std::memcmp(p, kSyncMagic, avail) == 0;
    case 'O': case 'R': return len == 2;
    case 'L': return len >= 9 && (avail == 0 || (p[0] >= '0' && p[0] <= '7'));  // uint8 log_level, uint64 timestamp
    case 'C': return len >= 11 && (avail == 0 || (p[0] >= '0' && p[0] <= '7'));  // + uint16 tag
    case 'F': {
      // "<name>:<fields>", the name printable without spaces.
      const void* colon = std::memchr(p, ':', avail);
      const std::size_t name = colon ? static_cast<std::size_t>(static_cast<const std::uint8_t*>(colon) - p) : avail;
      return len >= 2 && (name > 0 || avail == 0) &&
             std::all_of(p, p + name, [](std::uint8_t c) { return c > 0x20 && c <= 0x7e; });
    }
    case 'A': {
      if (len < 4) return false;
      if (avail < 3) return true;
      const std::string name(reinterpret_cast<const char*>(p + 3), avail - 3);
      if (avail == len) return formats_.count(name) > 0 || name == prev.format;
      for (const auto& [format, fields] : formats_) {
        if (format.compare(0, name.size(), name) == 0) return true;
      }
      return prev.format.compare(0, name.size(), name) == 0;
    }
    case 'I': case 'P': case 'M': case 'Q': {
      const std::size_t k = (type == 'M' || type == 'Q') ? 1 : 0;  // M / Q: uint8 is_continued first
      if (len < k + 1 || avail < k + 1) return len >= k + 1;
      const std::size_t key = p[k];
      if (key == 0 || key > len - k - 1) return false;
      if (avail >= k + 1 + key) return PrintableKey(p + k + 1, key);
      return std::all_of(p + k + 1, p + avail, [](std::uint8_t c) { return c >= 0x20 && c <= 0x7e; });
    }
    case 'D': {
      if (len < 2) return false;
      if (avail < 2) return DataRecordSize(len);
      const std::uint16_t id = U16(p);
      if (prev.msg_id == id) return true;  // the 'A' just before: its sizes are not known yet
      const auto it = subs_.find(id);
      return it != subs_.end() && len - 2 >= it->second.min_size && len - 2 <= it->second.max_size;
    }
    default: return false;
  }
}

bool Parser::DataRecordSize(std::size_t len) const {
  for (const auto& [id, sub] : subs_) {
    if (len >= 2 + sub.min_size && len <= 2 + sub.max_size) return true;
  }
  return false;
}

bool Parser::FollowedByValid(std::size_t at, std::size_t after, std::size_t end) const {
  if (after == end || PlausibleAt(after, end, IntroducedBy(at), true)) return true;
  if (after > end || end - after < kMessageHeaderBytes) return false;
  // One damaged header right after an intact record (that record is not lost with it):
  // - one of its type and msg_id damaged, the other intact, its size a data record's of that
  //   subscription, leading to a record (bytes read out of step rarely match all of this);
  const std::size_t len = U16(d_ + after);
  const bool is_data = static_cast<char>(d_[after + 2]) == 'D';
  const auto sub = end - after >= kMessageHeaderBytes + 2 ? subs_.find(U16(d_ + after + kMessageHeaderBytes)) : subs_.end();
  const bool sized = sub != subs_.end() && len >= 2 + sub->second.min_size && len <= 2 + sub->second.max_size;
  if ((is_data && DataRecordSize(len)) || (!is_data && sized)) {
    const std::size_t next = after + kMessageHeaderBytes + len;
    if (next == end || PlausibleAt(next, end, Introduced{}, true)) return true;
  }
  // - its size damaged: a 'D' of a subscription whose own data size leads to a record.
  if (!is_data || sub == subs_.end()) return false;
  for (const std::size_t size : {sub->second.min_size, sub->second.max_size}) {
    const std::size_t next = after + kMessageHeaderBytes + 2 + size;
    if (next == end || PlausibleAt(next, end, Introduced{}, true)) return true;
  }
  return false;
}

std::optional<std::size_t> Parser::Resync(std::size_t from, std::size_t end) const {
  for (std::size_t at = from; at + kMessageHeaderBytes <= end; ++at) {
    if (!PlausibleAt(at, end, Introduced{}, false)) continue;
    const std::size_t next = at + kMessageHeaderBytes + U16(d_ + at);
    if (next == end || PlausibleAt(next, end, IntroducedBy(at), true)) return at;
  }
  return std::nullopt;
}

void Parser::NoteDamage(std::size_t begin, std::size_t resume, const std::string& what) {
  LogDamage d(begin, resume, what);
  // Walk the skipped bytes by their own record headers while those stay inside the range; a 'D'
  // is given to its subscription, or to the only subscription whose data size matches (a damaged
  // msg_id), else counted as unidentified.
  std::size_t at = begin;
  while (at < resume) {
    if (resume - at < kMessageHeaderBytes) {
      ++d.records_unidentified;
      break;
    }
    const std::size_t len = U16(d_ + at);
    const char type = static_cast<char>(d_[at + 2]);
    if (len > resume - at - kMessageHeaderBytes || !KnownType(type)) {
      ++d.records_unidentified;
      break;
    }
    if (type == 'D' && len >= 2) {
      const std::size_t size = len - 2;
      std::optional<std::size_t> topic;
      if (const auto it = subs_.find(U16(d_ + at + kMessageHeaderBytes));
          it != subs_.end() && size >= it->second.min_size && size <= it->second.max_size) {
        topic = it->second.topic;
      } else {
        int matches = 0;
        for (const auto& [id, sub] : subs_) {
          if (size >= sub.min_size && size <= sub.max_size) ++matches, topic = sub.topic;
        }
        if (matches != 1) topic.reset();
      }
      if (topic) {
        const ULogTopic& t = out_.topics[*topic];
        ++d.rows_lost[t.name + " " + std::to_string(t.multi_id)];
      } else {
        ++d.records_unidentified;
      }
    }
    at += kMessageHeaderBytes + len;
  }
  out_.damage.push_back(std::move(d));
}
}  // namespace gyrocomp::ulog_detail
