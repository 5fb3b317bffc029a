// PX4 ULog reader (include/gyrocomp/io/ulog.h). Section numbers ("spec: ...") refer to the
// PX4 User Guide page "ULog File Format"; behaviour at the edges follows PX4/pyulog core.py.
// How recovery tells a damaged record from an intact one is in ulog_recovery.cc.
#include "gyrocomp/io/ulog.h"
#include "gyrocomp/io/log_damage.h"
#include "gyrocomp/io/mapped_file.h"
#include "gyrocomp/io/io.h"
#include "ulog_parser.h"

#include <cmath>
#include <cstring>
#include <functional>
#include <fstream>
#include <memory>
#include <string_view>
#include <utility>

namespace gyrocomp {
namespace ulog_detail {

Result<ULogContents> Parser::Run() {
  if (n_ < kHeaderBytes) {
    return Bad(n_, "file too short for the 16-byte ULog header (" + std::to_string(n_) + " bytes)");
  }
  if (!HasULogMagic(d_, n_)) return Bad(0, "not a ULog file (bad magic bytes)");
  out_.version = d_[7];
  out_.start_timestamp_us = U64(d_ + 8);
  if (auto e = ParseAll()) return *e;
  for (auto& [id, sub] : subs_) FlushWindow(sub);
  if (const std::string w = DamageWarning(out_.source, out_.damage); !w.empty()) out_.warnings.push_back(w);
  return std::move(out_);
}

// Messages from the header to the end of the file. spec "Flag Bits Message": with
// DATA_APPENDED, the main data ends at the first appended offset and each appended segment runs
// to the next one (pyulog _load_file does the same); a message that crosses the end of its
// segment is a truncated last record.
std::optional<Error> Parser::ParseAll() {
  std::size_t pos = kHeaderBytes;
  std::size_t end = n_;
  std::vector<std::size_t> segment_ends;  // set once the flag bits message was read
  std::size_t next_segment = 0;
  bool segments_known = false;
  while (true) {
    if (!segments_known && !first_message_) {
      segments_known = true;
      if (!out_.appended_offsets.empty()) {
        for (std::size_t i = 1; i < out_.appended_offsets.size(); ++i) {
          segment_ends.push_back(static_cast<std::size_t>(out_.appended_offsets[i]));
        }
        segment_ends.push_back(n_);
        end = static_cast<std::size_t>(out_.appended_offsets[0]);
      }
    }
    if (pos >= end) {
      if (next_segment >= segment_ends.size()) break;
      pos = end;
      end = segment_ends[next_segment++];
      continue;
    }
    if (end - pos < kMessageHeaderBytes) {
      Warn(pos, "truncated last record (" + std::to_string(end - pos) + " of 3 header bytes) dropped");
      pos = end;
      continue;
    }
    const std::size_t len = U16(d_ + pos);
    const char type = static_cast<char>(d_[pos + 2]);
    const bool recover = !options_.strict;
    if (len > end - pos - kMessageHeaderBytes) {
      // A size running past the segment: the last record cut short, or (recovery) a damaged size
      // field with valid records after it.
      if (recover) {
        if (const auto next = Resync(pos + 1, end)) {
          NoteDamage(pos, *next, "message size " + std::to_string(len) + " runs past the end of the data");
          pos = *next;
          continue;
        }
      }
      Warn(pos, "truncated last record (type '" + std::string(1, type) + "', " +
                    std::to_string(end - pos - kMessageHeaderBytes) + " of " + std::to_string(len) +
                    " payload bytes) dropped");
      pos = end;
      continue;
    }
    const std::size_t after = pos + kMessageHeaderBytes + len;
    std::optional<Error> e;
    if (recover && !first_message_ && !KnownType(type) && !FollowedByValid(pos, after, end)) {
      e = Bad(pos, "message type " + std::to_string(static_cast<unsigned>(static_cast<std::uint8_t>(type))) +
                       " unknown and no valid message after it");
    } else if (recover && !FollowedByValid(pos, after, end)) {
      // A record is decoded only when a valid message follows it: a size damaged into the next
      // record would otherwise make a row of bytes from two records.
      e = Bad(pos, "'" + std::string(1, type) + "' message of " + std::to_string(len) +
                       " bytes not followed by a valid message (a damaged size or a cut record)");
    } else {
      e = ParseMessage(type, pos, d_ + pos + kMessageHeaderBytes, len);
    }
    if (e) {
      // Unknown incompatible flags (spec "Flag Bits Message": a parser must not read such a log)
      // are a refusal even when recovering, not a damaged record to skip.
      if (!recover || unknown_incompat_) return e;
      // Resume right after the refused record when its size leads to a valid record (only the
      // record itself was damaged, e.g. its msg_id), else at the next valid record after it.
      std::optional<std::size_t> next;
      if (after <= end && (after == end || PlausibleAt(after, end, Introduced{}, true))) next = after;
      if (!next) next = Resync(pos + 1, end);
      std::string what = e->message;
      if (const auto cut = what.find(": byte "); cut != std::string::npos) {
        if (const auto colon = what.find(": ", cut + 7); colon != std::string::npos) what = what.substr(colon + 2);
      }
      NoteDamage(pos, next.value_or(end), what);
      first_message_ = false;
      pos = next.value_or(end);
      continue;
    }
    ++out_.num_messages;
    first_message_ = false;
    pos += kMessageHeaderBytes + len;
    if (release_ && pos - released_ >= (std::size_t{64} << 20)) release_(released_ = pos);
  }
  return std::nullopt;
}

std::optional<Error> Parser::ParseMessage(char type, std::size_t at, const std::uint8_t* p, std::size_t len) {
  switch (type) {
    case 'B': return ParseFlagBits(at, p, len);
    case 'F': return ParseFormat(at, p, len);
    case 'I': case 'M': case 'P': case 'Q': return ParseKeyValue(type, at, p, len);
    case 'A': return ParseSubscription(at, p, len);
    case 'D': return ParseData(at, p, len);
    case 'R':
      if (len < 2) return Bad(at, "unsubscription ('R') of " + std::to_string(len) + " bytes, needs 2");
      subs_.erase(U16(p));
      return std::nullopt;
    case 'O':
      if (len < 2) return Bad(at, "dropout ('O') of " + std::to_string(len) + " bytes, needs 2");
      out_.dropouts.push_back({at, U16(p)});
      return std::nullopt;
    default:
      return std::nullopt;  // 'L', 'C', 'S' and message types added after this reader: skipped
  }
}

std::optional<Error> Parser::ParseFlagBits(std::size_t at, const std::uint8_t* p, std::size_t len) {
  // spec "Flag Bits Message": uint8 compat_flags[8], uint8 incompat_flags[8],
  // uint64 appended_offsets[3]; must be the first message.
  if (!first_message_) return Bad(at, "flag bits message ('B') is not the first message");
  if (len < 40) return Bad(at, "flag bits message ('B') of " + std::to_string(len) + " bytes, needs 40");
  const std::uint8_t* incompat = p + 8;
  unknown_incompat_ = (incompat[0] & ~1u) != 0;
  for (int i = 1; i < 8; ++i) unknown_incompat_ = unknown_incompat_ || incompat[i] != 0;
  if (unknown_incompat_) return Bad(at, "unknown incompatible flag bits set: cannot parse the log");
  if ((incompat[0] & 1u) == 0) return std::nullopt;
  std::size_t after = at + kMessageHeaderBytes + len;
  for (int i = 0; i < 3; ++i) {
    const std::uint64_t off = U64(p + 16 + 8 * i);
    if (off == 0) continue;
    if (off < after || off > n_) {
      return Bad(at, "appended-data offset " + std::to_string(off) + " outside [" + std::to_string(after) + ", " +
                         std::to_string(n_) + "] (file size or not increasing)");
    }
    out_.appended_offsets.push_back(off);
    after = static_cast<std::size_t>(off);
  }
  return std::nullopt;
}

std::optional<Error> Parser::ParseFormat(std::size_t at, const std::uint8_t* p, std::size_t len) {
  // spec "Format Message": char format[] = "message_name:field0;field1;", field = "type name".
  const std::string text(reinterpret_cast<const char*>(p), len);
  const auto colon = text.find(':');
  if (colon == std::string::npos || colon == 0) return Bad(at, "format message ('F') without 'name:'");
  const std::string name = text.substr(0, colon);
  std::vector<FieldDef> fields;
  std::size_t i = colon + 1;
  while (i < text.size()) {
    std::size_t semi = text.find(';', i);
    if (semi == std::string::npos) semi = text.size();
    const std::string item = text.substr(i, semi - i);
    i = semi + 1;
    if (item.empty()) continue;
    const auto space = item.find(' ');
    if (space == std::string::npos || space == 0 || space + 1 == item.size()) {
      return Bad(at, "format '" + name + "': field '" + item + "' is not 'type name'");
    }
    FieldDef f;
    f.type = item.substr(0, space);
    f.name = item.substr(space + 1);
    const auto lb = f.type.find('[');
    if (lb != std::string::npos) {
      const auto rb = f.type.find(']', lb);
      const std::string count = rb == std::string::npos ? "" : f.type.substr(lb + 1, rb - lb - 1);
      if (count.empty() || count.size() > 5 || count.find_first_not_of("0123456789") != std::string::npos ||
          rb + 1 != f.type.size() || std::stoul(count) == 0) {
        return Bad(at, "format '" + name + "': bad array size in '" + f.type + "'");
      }
      f.array_size = std::stoul(count);
      f.type = f.type.substr(0, lb);
    }
    fields.push_back(std::move(f));
  }
  formats_[name] = std::move(fields);
  return std::nullopt;
}

std::optional<Error> Parser::ParseKeyValue(char type, std::size_t at, const std::uint8_t* p, std::size_t len) {
  // spec: 'I' = uint8 key_len, char key[key_len] ("type name"), value; 'M' has a leading uint8
  // is_continued, 'Q' a leading uint8 default_types.
  std::size_t skip = (type == 'M' || type == 'Q') ? 1 : 0;
  if (len < skip + 1) return Bad(at, std::string("'") + type + "' message too short");
  const std::size_t key_len = p[skip];
  if (key_len > len - skip - 1) {
    return Bad(at, std::string("'") + type + "' key length " + std::to_string(key_len) + " exceeds the message");
  }
  const std::string key(reinterpret_cast<const char*>(p + skip + 1), key_len);
  const auto space = key.find(' ');
  if (space == std::string::npos) return Bad(at, std::string("'") + type + "' key '" + key + "' is not 'type name'");
  const std::string vtype = key.substr(0, space);
  const std::string name = key.substr(space + 1);
  const std::uint8_t* v = p + skip + 1 + key_len;
  const std::size_t vlen = len - skip - 1 - key_len;
  if (type == 'I' && vtype.rfind("char[", 0) == 0) {
    out_.info[name] = std::string(reinterpret_cast<const char*>(v), vlen);
  } else if (type == 'P') {
    if (vlen != 4 || (vtype != "int32_t" && vtype != "float")) {
      return Bad(at, "parameter '" + name + "' of type " + vtype + " with " + std::to_string(vlen) +
                         " value bytes (int32_t or float, 4 bytes)");
    }
    out_.parameters[name] = vtype == "float" ? static_cast<double>(F32(v)) : static_cast<double>(static_cast<std::int32_t>(U32(v)));
  }
  return std::nullopt;
}

std::optional<Error> Parser::Flatten(std::size_t at, const std::string& type, const std::string& prefix, int depth,
                                     std::vector<FlatField>* fields, std::size_t* size, std::size_t* padding_tail) {
  if (depth > kMaxNestingDepth) return Bad(at, "formats nested deeper than " + std::to_string(kMaxNestingDepth));
  if (depth == 0) flatten_steps_ = 0;
  const auto it = formats_.find(type);
  if (it == formats_.end()) return Bad(at, "no format ('F') for type '" + type + "'");
  for (const FieldDef& f : it->second) {
    const std::size_t count = f.array_size == 0 ? 1 : f.array_size;
    for (std::size_t k = 0; k < count; ++k) {
      if (++flatten_steps_ > kMaxFlattenSteps) return Bad(at, "format '" + type + "' has too many (nested) fields");
      const std::string name = prefix + f.name + (f.array_size ? "[" + std::to_string(k) + "]" : "");
      if (const std::size_t b = BasicSize(f.type); b > 0) {
        fields->push_back({name, f.type, *size});
        *size += b;
        // pyulog _parse_format: trailing _padding fields may be left out of 'D' messages.
        *padding_tail = f.name.rfind("_padding", 0) == 0 && depth == 0 ? *padding_tail + b : 0;
      } else {
        if (auto e = Flatten(at, f.type, name + ".", depth + 1, fields, size, padding_tail)) return e;
        *padding_tail = 0;
      }
      if (*size > 65535) return Bad(at, "format '" + type + "' is larger than a ULog message can be");
    }
  }
  return std::nullopt;
}

std::optional<Error> Parser::ParseSubscription(std::size_t at, const std::uint8_t* p, std::size_t len) {
  // spec "Subscription Message": uint8 multi_id, uint16 msg_id, char message_name[].
  if (len < 4) return Bad(at, "subscription ('A') of " + std::to_string(len) + " bytes, needs at least 4");
  ULogTopic topic;
  topic.multi_id = p[0];
  topic.msg_id = U16(p + 1);
  topic.name.assign(reinterpret_cast<const char*>(p + 3), len - 3);
  std::vector<FlatField> fields;
  Subscription s;
  std::size_t padding_tail = 0;
  if (auto e = Flatten(at, topic.name, "", 0, &fields, &s.max_size, &padding_tail)) return e;
  s.min_size = s.max_size - padding_tail;
  auto find = [&](const std::string& name, const char* type) -> std::optional<std::size_t> {
    for (const FlatField& f : fields) {
      if (f.name == name) return f.type == type ? std::optional<std::size_t>(f.offset) : std::nullopt;
    }
    return std::nullopt;
  };
  const bool gyro = topic.name == "sensor_gyro";
  const bool accel = topic.name == "sensor_accel", baro = topic.name == "sensor_baro";
  const bool combined = topic.name == "sensor_combined";
  const auto ts = find("timestamp", "uint64_t");
  const auto x = find(baro ? "pressure" : (combined ? "gyro_rad[0]" : "x"), "float");
  const auto y = baro ? x : find(combined ? "gyro_rad[1]" : "y", "float");
  const auto z = baro ? x : find(combined ? "gyro_rad[2]" : "z", "float");
  if (gyro || combined || accel || baro) {
    if (ts && x && y && z && *ts + 8 <= s.min_size && *x + 4 <= s.min_size && *y + 4 <= s.min_size && *z + 4 <= s.min_size) {
      s.kind = gyro ? 1 : combined ? 2 : accel ? 3 : 4;
      s.g.timestamp = *ts; s.g.x = *x; s.g.y = *y; s.g.z = *z;
      if (const auto t = find("temperature", "float"); !combined && t && *t + 4 <= s.min_size) {
        s.g.temperature = *t;
        s.g.has_temperature = true;
      }
      if (const auto id = find("device_id", "uint32_t"); !combined && id && *id + 4 <= s.min_size) {
        s.g.device_id = *id;
        s.g.has_device_id = true;
      }
      if (gyro || combined) {
        auto& list = gyro ? out_.gyros : out_.combined;
        s.series = static_cast<int>(list.size());
        list.push_back(ULogGyroSeries{});
        list.back().topic = topic.name;
        list.back().multi_id = topic.multi_id;
      } else if (accel) {
        s.series = static_cast<int>(out_.accels.size());
        out_.accels.push_back(ULogAccelSeries{});
        out_.accels.back().multi_id = topic.multi_id;
      } else {
        s.series = static_cast<int>(out_.baros.size());
        out_.baros.push_back(ULogBaroSeries{});
        out_.baros.back().multi_id = topic.multi_id;
      }
    } else {
      Warn(at, topic.name + " has no uint64 timestamp and float value fields this reader knows; not read");
    }
  }
  if (const char* field = StateField(topic.name)) {
    // One byte: bool or uint8_t (msg/ActuatorArmed.msg bool armed, msg/VehicleStatus.msg uint8
    // arming_state, msg/VehicleLandDetected.msg bool landed).
    auto v = find(field, "bool");
    if (!v) v = find(field, "uint8_t");
    if (ts && v && *ts + 8 <= s.min_size && *v + 1 <= s.min_size) {
      s.kind = 5;
      s.g.timestamp = *ts, s.g.x = *v;
      s.series = static_cast<int>(out_.states.size());
      out_.states.push_back(ULogStateSeries{topic.name, field, topic.multi_id, {}, {}});
    } else {
      Warn(at, topic.name + " has no uint64 timestamp and one-byte '" + field + "' field; its state is not read");
    }
  }
  s.topic = out_.topics.size();
  out_.topics.push_back(topic);
  subs_[topic.msg_id] = std::move(s);
  return std::nullopt;
}

std::optional<Error> Parser::ParseData(std::size_t at, const std::uint8_t* p, std::size_t len) {
  // spec "Logged Data Message": uint16 msg_id, uint8 data[] (the format's fields, packed).
  if (len < 2) return Bad(at, "data message ('D') of " + std::to_string(len) + " bytes, needs at least 2");
  const int msg_id = U16(p);
  const auto it = subs_.find(msg_id);
  if (it == subs_.end()) return Bad(at, "data ('D') for msg_id " + std::to_string(msg_id) + " without a subscription ('A')");
  Subscription& s = it->second;
  const std::size_t size = len - 2;
  if (size < s.min_size || size > s.max_size) {
    return Bad(at, "data ('D') for '" + out_.topics[s.topic].name + "' has " + std::to_string(size) +
                       " bytes; its format has " + std::to_string(s.min_size) +
                       (s.min_size == s.max_size ? "" : " to " + std::to_string(s.max_size)));
  }
  ++out_.topics[s.topic].rows;
  if (s.kind == 5) {
    DecodeState(s, p + 2);
  } else if (s.kind != 0) {
    DecodeRow(s, p + 2);
  }
  return std::nullopt;
}

// The first row's device id, and a warning (once) when a later row's differs.
void Parser::NoteDeviceId(Subscription& s, const std::uint8_t* row, const std::string& what, std::size_t rows,
                          std::optional<std::uint32_t>* device_id) {
  if (!s.g.has_device_id) return;
  const std::uint32_t id = U32(row + s.g.device_id);
  if (!*device_id) {
    *device_id = id;
  } else if (**device_id != id && !s.device_id_change_reported) {
    s.device_id_change_reported = true;
    out_.warnings.push_back(out_.source + ": " + what + ": device_id changes from " + std::to_string(**device_id) +
                            " to " + std::to_string(id) + " at row " + std::to_string(rows) + " (the first is reported)");
  }
}

void Parser::DecodeRow(Subscription& s, const std::uint8_t* row) {
  RowValues v;
  v.t = U64(row + s.g.timestamp);
  v.x = F32(row + s.g.x);
  v.y = F32(row + s.g.y);
  v.z = F32(row + s.g.z);
  if (s.g.has_temperature) v.temp = F32(row + s.g.temperature);
  const auto series = static_cast<std::size_t>(s.series);
  // Device ids are checked on every logged row, averaged or not.
  if (s.kind == 3) {
    ULogAccelSeries& a = out_.accels[series];
    NoteDeviceId(s, row, "sensor_accel multi_id " + std::to_string(a.multi_id), a.timestamp_us.size() + 1, &a.device_id);
  } else if (s.kind == 4) {
    ULogBaroSeries& b = out_.baros[series];
    NoteDeviceId(s, row, "sensor_baro multi_id " + std::to_string(b.multi_id), b.timestamp_us.size() + 1, &b.device_id);
  } else {
    ULogGyroSeries& g = (s.kind == 1 ? out_.gyros : out_.combined)[series];
    NoteDeviceId(s, row, g.topic + " multi_id " + std::to_string(g.multi_id), g.timestamp_us.size() + 1, &g.device_id);
  }
  const std::uint64_t w = options_.average_window_us;
  if (w == 0) {
    PushRow(s, v);
    return;
  }
  if (s.count > 0 && v.t / w != s.window) FlushWindow(s);
  s.window = v.t / w;
  ++s.count;
  s.sum_t += static_cast<double>(v.t);
  s.sum_x += v.x, s.sum_y += v.y, s.sum_z += v.z, s.sum_temp += v.temp;
}

const char* Parser::StateField(const std::string& topic) {
  if (topic == "actuator_armed") return "armed";
  if (topic == "vehicle_status") return "arming_state";
  if (topic == "vehicle_land_detected") return "landed";
  return nullptr;
}

void Parser::DecodeState(const Subscription& s, const std::uint8_t* row) {
  ULogStateSeries& st = out_.states[static_cast<std::size_t>(s.series)];
  const int v = row[s.g.x];
  if (!st.value.empty() && st.value.back() == v) return;
  st.timestamp_us.push_back(U64(row + s.g.timestamp));
  st.value.push_back(v);
}

void Parser::FlushWindow(Subscription& s) {
  if (s.count == 0 || s.kind == 0 || s.kind == 5) return;
  const double n = static_cast<double>(s.count);
  RowValues v;
  v.t = static_cast<std::uint64_t>(std::llround(s.sum_t / n));
  v.x = s.sum_x / n, v.y = s.sum_y / n, v.z = s.sum_z / n, v.temp = s.sum_temp / n;
  PushRow(s, v);
  s.count = 0;
  s.sum_t = s.sum_x = s.sum_y = s.sum_z = s.sum_temp = 0.0;
}

void Parser::PushRow(const Subscription& s, const RowValues& v) {
  const auto series = static_cast<std::size_t>(s.series);
  if ((s.kind == 3 || s.kind == 4) && !options_.keep_accel_baro) return;  // ULogReadOptions
  if (s.kind == 3) {
    ULogAccelSeries& a = out_.accels[series];
    a.timestamp_us.push_back(v.t);
    a.x_m_s2.push_back(v.x);
    a.y_m_s2.push_back(v.y);
    a.z_m_s2.push_back(v.z);
    if (s.g.has_temperature) a.temperature_c.push_back(v.temp);
  } else if (s.kind == 4) {
    ULogBaroSeries& b = out_.baros[series];
    b.timestamp_us.push_back(v.t);
    b.pressure_pa.push_back(v.x);
    if (s.g.has_temperature) b.temperature_c.push_back(v.temp);
  } else {
    ULogGyroSeries& g = (s.kind == 1 ? out_.gyros : out_.combined)[series];
    g.timestamp_us.push_back(v.t);
    if (options_.gyro_instance && g.multi_id != *options_.gyro_instance) return;  // counted only
    g.x_rad_s.push_back(v.x);
    g.y_rad_s.push_back(v.y);
    g.z_rad_s.push_back(v.z);
    if (s.g.has_temperature) g.temperature_c.push_back(v.temp);
  }
}


}  // namespace ulog_detail

using ulog_detail::kMagic;
using ulog_detail::Parser;

bool HasULogMagic(const std::uint8_t* data, std::size_t size) {
  return size >= sizeof kMagic && std::memcmp(data, kMagic, sizeof kMagic) == 0;
}

namespace {

Result<ULogContents> ParseULogWith(const std::uint8_t* data, std::size_t size, const std::string& source,
                                   const ULogReadOptions& options, std::function<void(std::size_t)> release) {
  Parser parser(data, size, source, options, std::move(release));
  Result<ULogContents> r = parser.Run();
  if (!r) return r;
  // Drop subscriptions without rows (pyulog keeps only data it saw).
  for (auto* list : {&r->gyros, &r->combined}) {
    std::vector<ULogGyroSeries> kept;
    for (auto& g : *list) {
      if (!g.timestamp_us.empty()) kept.push_back(std::move(g));
    }
    *list = std::move(kept);
  }
  std::erase_if(r->accels, [](const ULogAccelSeries& a) { return a.timestamp_us.empty(); });
  std::erase_if(r->baros, [](const ULogBaroSeries& b) { return b.timestamp_us.empty(); });
  std::erase_if(r->states, [](const ULogStateSeries& v) { return v.timestamp_us.empty(); });
  return r;
}

}  // namespace

Result<ULogContents> ParseULog(const std::uint8_t* data, std::size_t size, const std::string& source,
                               const ULogReadOptions& options) {
  return ParseULogWith(data, size, source, options, nullptr);
}

Result<ULogContents> ReadULog(const std::string& path, const ULogReadOptions& options) {
  if (Result<MappedFile> map = MappedFile::Open(path); map.ok()) {
    MappedFile* m = &*map;
    return ParseULogWith(m->data(), m->size(), path, options, [m](std::size_t offset) { m->ReleaseBefore(offset); });
  }
  Result<std::string> bytes = ReadFileBytes(path);
  if (!bytes.ok()) return bytes.error();
  return ParseULog(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size(), path, options);
}

std::string ULogContents::BriefReport() const {
  std::string s = source + ": ULog v" + std::to_string(version) + ", " + std::to_string(num_messages) + " messages, " +
                  std::to_string(topics.size()) + " subscriptions, " + std::to_string(gyros.size()) +
                  " sensor_gyro and " + std::to_string(combined.size()) + " sensor_combined instances with data, " +
                  std::to_string(dropouts.size()) + " dropouts";
  if (!appended_offsets.empty()) s += ", " + std::to_string(appended_offsets.size()) + " appended segments";
  return s;
}

}  // namespace gyrocomp
