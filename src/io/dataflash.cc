// ArduPilot DataFlash reader (include/gyrocomp/io/dataflash.h). Record layout and format
// characters: ArduPilot libraries/AP_Logger/LogStructure.h; edge behaviour: pymavlink DFReader.py.
#include "gyrocomp/io/dataflash.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/io/log_damage.h"
#include "gyrocomp/io/mapped_file.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <cstring>
#include <fstream>
#include <optional>
#include <utility>

namespace gyrocomp {

namespace {

constexpr std::uint8_t kHead1 = 0xA3;
constexpr std::uint8_t kHead2 = 0x95;
constexpr int kFmtType = 0x80;     // FMT: "BBnNZ" Type,Length,Name,Format,Columns
constexpr int kFmtLength = 89;     // 3 + 1 + 1 + 4 + 16 + 64
constexpr std::size_t kHeaderBytes = 3;

// Bytes of one format character (DFReader FORMAT_TO_STRUCT), 0 if unknown.
std::size_t CharSize(char c) {
  switch (c) {
    case 'b': case 'B': case 'M': return 1;
    case 'h': case 'H': case 'c': case 'C': case 'g': return 2;
    case 'i': case 'I': case 'f': case 'e': case 'E': case 'L': case 'n': return 4;
    case 'd': case 'q': case 'Q': return 8;
    case 'N': return 16;
    case 'Z': case 'a': return 64;
    default: return 0;
  }
}

std::uint64_t ULe(const std::uint8_t* p, std::size_t bytes) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < bytes; ++i) v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
  return v;
}

// A numeric field as a double (float32 widened exactly; the x0.01 / x1e-7 kinds scaled as
// DFReader does); nullopt for strings and arrays.
std::optional<double> Numeric(char c, const std::uint8_t* p) {
  switch (c) {
    case 'b': return static_cast<double>(static_cast<std::int8_t>(p[0]));
    case 'B': case 'M': return static_cast<double>(p[0]);
    case 'h': return static_cast<double>(static_cast<std::int16_t>(ULe(p, 2)));
    case 'H': return static_cast<double>(ULe(p, 2));
    case 'i': return static_cast<double>(static_cast<std::int32_t>(ULe(p, 4)));
    case 'I': return static_cast<double>(ULe(p, 4));
    case 'q': return static_cast<double>(static_cast<std::int64_t>(ULe(p, 8)));
    case 'Q': return static_cast<double>(ULe(p, 8));
    case 'c': return static_cast<double>(static_cast<std::int16_t>(ULe(p, 2))) * 0.01;
    case 'C': return static_cast<double>(ULe(p, 2)) * 0.01;
    case 'e': return static_cast<double>(static_cast<std::int32_t>(ULe(p, 4))) * 0.01;
    case 'E': return static_cast<double>(ULe(p, 4)) * 0.01;
    case 'L': return static_cast<double>(static_cast<std::int32_t>(ULe(p, 4))) * 1.0e-7;
    case 'f': {
      const auto bits = static_cast<std::uint32_t>(ULe(p, 4));
      float f;
      std::memcpy(&f, &bits, sizeof f);
      return static_cast<double>(f);
    }
    case 'd': {
      const std::uint64_t bits = ULe(p, 8);
      double d;
      std::memcpy(&d, &bits, sizeof d);
      return d;
    }
    default: return std::nullopt;
  }
}

// A NUL-terminated char array field.
std::string Text(const std::uint8_t* p, std::size_t n) {
  std::size_t len = 0;
  while (len < n && p[len] != 0) ++len;
  return std::string(reinterpret_cast<const char*>(p), len);
}

std::vector<std::string> SplitComma(const std::string& s) {
  std::vector<std::string> out;
  if (s.empty()) return out;
  std::size_t b = 0;
  while (true) {
    const auto e = s.find(',', b);
    out.push_back(s.substr(b, e == std::string::npos ? std::string::npos : e - b));
    if (e == std::string::npos) break;
    b = e + 1;
  }
  return out;
}

// "file: byte N: what" -> "what" (a damage entry gives the place itself).
std::string WithoutPlace(const std::string& message) {
  const auto b = message.find(": byte ");
  const auto c = b == std::string::npos ? std::string::npos : message.find(": ", b + 7);
  return c == std::string::npos ? message : message.substr(c + 2);
}

// A known message type: its FMT and the byte offset of each field within the payload.
struct Layout {
  DataFlashFormat fmt;
  std::vector<std::size_t> offsets;  // one per format character
  bool decodable = true;             // every format character known and sizes add up
};

std::optional<std::size_t> FieldIndex(const Layout& l, const std::string& label) {
  for (std::size_t i = 0; i < l.fmt.labels.size() && i < l.fmt.format.size(); ++i) {
    if (l.fmt.labels[i] == label) return i;
  }
  return std::nullopt;
}

class Parser {
 public:
  Parser(const std::uint8_t* d, std::size_t n, std::string source, DataFlashReadOptions options,
         std::function<void(std::size_t)> release)
      : d_(d), n_(n), options_(options), release_(std::move(release)) {
    out_.source = std::move(source);
  }
  Result<DataFlashContents> Run();

 private:
  Error Bad(std::size_t at, const std::string& what) const {
    return InvalidInput(out_.source + ": byte " + std::to_string(at) + ": " + what);
  }
  std::optional<Error> AddFormat(std::size_t at, const std::uint8_t* p);
  // Recovery (DataFlashReadOptions::strict false). HeaderAt: A3 95 and a type some FMT defined
  // (or `extra_type`, the type a FMT record being checked defines) at `at`; a tail of fewer than 3
  // bytes that starts like a header also passes (a cut last record). RecordAt: a header whose
  // type's length fits in the file and is followed by another header or the end of the file.
  bool HeaderAt(std::size_t at, int extra_type = -1) const;
  bool RecordAt(std::size_t at) const;
  // A header with one part damaged and a valid header where the record would end: A3 or 95
  // flipped (the type, intact, gives the length), or A3 95 intact with a type no FMT defined (some
  // defined type's length reaches the next header). An intact record before it is then kept.
  bool DamagedHeaderAt(std::size_t at) const;
  std::optional<std::size_t> Resync(std::size_t from) const;
  void NoteDamage(std::size_t begin, std::size_t resume, const std::string& what);
  // "IMU 1" for an IMU record (instance from field I, or the message name), else the name.
  std::string TopicOf(const Layout& l, const std::uint8_t* payload) const;
  void TakeImu(const Layout& l, const std::uint8_t* p);
  void TakeParameter(const Layout& l, const std::uint8_t* p, std::size_t at);
  // ARM (field ArmState) and EV (field Id) records with TimeUS: DataFlashContents::arm_states / events.
  void TakeState(const Layout& l, const std::uint8_t* p);
  // ImuRow fields: time, gyro x y z, accel x y z, T.
  static constexpr int kRowFields = 8;
  using ImuRow = std::array<double, kRowFields>;
  void PushImu(DataFlashImuSeries& s, const ImuRow& r, bool has_t, bool has_acc);
  void FlushWindow(int instance);

  struct Window {
    std::uint64_t index = 0;
    std::size_t count = 0;
    ImuRow sum{};
    bool has_t = false, has_acc = false;
  };
  const std::uint8_t* d_;
  std::size_t n_;
  DataFlashReadOptions options_;
  std::function<void(std::size_t)> release_;
  std::size_t released_ = 0;
  std::map<int, Window> windows_;  // instance -> open window (average_window_us > 0)
  DataFlashContents out_;
  std::map<int, Layout> layouts_;
  std::map<int, std::size_t> imu_index_;  // instance -> index in out_.imus
};

bool Parser::HeaderAt(std::size_t at, int extra_type) const {
  if (at >= n_) return at == n_;
  if (n_ - at < kHeaderBytes) return d_[at] == kHead1 && (n_ - at < 2 || d_[at + 1] == kHead2);
  if (d_[at] != kHead1 || d_[at + 1] != kHead2) return false;
  const int type = d_[at + 2];
  return type == extra_type || layouts_.count(type) > 0;
}

bool Parser::RecordAt(std::size_t at) const {
  if (!HeaderAt(at) || n_ - at < kHeaderBytes) return false;
  const int type = d_[at + 2];
  const std::size_t len = static_cast<std::size_t>(layouts_.at(type).fmt.length);
  if (len > n_ - at) return false;
  return HeaderAt(at + len, type == kFmtType ? d_[at + kHeaderBytes] : -1);
}

bool Parser::DamagedHeaderAt(std::size_t at) const {
  if (at >= n_ || n_ - at < kHeaderBytes) return false;
  const bool h1 = d_[at] == kHead1, h2 = d_[at + 1] == kHead2;
  const auto it = layouts_.find(d_[at + 2]);
  if (h1 != h2 && it != layouts_.end()) {
    return HeaderAt(at + static_cast<std::size_t>(it->second.fmt.length));
  }
  if (h1 && h2 && it == layouts_.end()) {
    for (const auto& [type, l] : layouts_) {
      if (l.fmt.length >= static_cast<int>(kHeaderBytes) && at + static_cast<std::size_t>(l.fmt.length) < n_ &&
          n_ - at - static_cast<std::size_t>(l.fmt.length) >= kHeaderBytes && HeaderAt(at + static_cast<std::size_t>(l.fmt.length))) {
        return true;
      }
    }
  }
  return false;
}

std::optional<std::size_t> Parser::Resync(std::size_t from) const {
  for (std::size_t at = from; at + kHeaderBytes <= n_; ++at) {
    if (d_[at] == kHead1 && RecordAt(at)) return at;
  }
  return std::nullopt;
}

std::string Parser::TopicOf(const Layout& l, const std::uint8_t* payload) const {
  const std::string& name = l.fmt.name;
  if (name != "IMU" && name != "IMU2" && name != "IMU3") return name;
  int instance = name == "IMU2" ? 1 : (name == "IMU3" ? 2 : 0);
  if (const auto i = FieldIndex(l, "I"); i && l.decodable) {
    if (const auto v = Numeric(l.fmt.format[*i], payload + l.offsets[*i])) instance = static_cast<int>(*v);
    // A damaged record's I may be anything: only an instance the log has is named.
    if (imu_index_.count(instance) == 0) return name + " ?";
  }
  return name + " " + std::to_string(instance);
}

void Parser::NoteDamage(std::size_t begin, std::size_t resume, const std::string& what) {
  LogDamage d(begin, resume, what);
  // Walk the skipped bytes by their headers while those stay inside the range. A record whose
  // header is damaged is told by its length when the gap to the next header is the length of one
  // message only (a flipped type byte, a flipped A3 95).
  std::size_t at = begin;
  while (at < resume) {
    const auto it = resume - at >= kHeaderBytes && d_[at] == kHead1 && d_[at + 1] == kHead2
                        ? layouts_.find(d_[at + 2]) : layouts_.end();
    if (it != layouts_.end()) {
      // An intact header: its record (cut short when it runs past the range).
      const std::size_t len = static_cast<std::size_t>(it->second.fmt.length);
      ++d.rows_lost[len <= n_ - at ? TopicOf(it->second, d_ + at + kHeaderBytes) : it->second.fmt.name + " ?"];
      if (len > resume - at) break;
      at += len;
      continue;
    }
    const Layout* only = nullptr;
    int matches = 0;
    for (const auto& [type, l] : layouts_) {
      if (static_cast<std::size_t>(l.fmt.length) == resume - at && (!only || only->fmt.name != l.fmt.name)) {
        ++matches;
        only = &l;
      }
    }
    if (matches == 1 && resume - at >= kHeaderBytes) {
      ++d.rows_lost[TopicOf(*only, d_ + at + kHeaderBytes)];
    } else {
      ++d.records_unidentified;
    }
    break;
  }
  out_.damage.push_back(std::move(d));
}

Result<DataFlashContents> Parser::Run() {
  Layout fmt;
  fmt.fmt = {kFmtType, kFmtLength, "FMT", "BBnNZ", {"Type", "Length", "Name", "Format", "Columns"}};
  fmt.offsets = {0, 1, 2, 6, 22};
  layouts_[kFmtType] = fmt;
  std::size_t pos = 0;
  while (pos < n_) {
    if (n_ - pos < kHeaderBytes) {
      out_.warnings.push_back(out_.source + ": byte " + std::to_string(pos) + ": truncated last record (" +
                              std::to_string(n_ - pos) + " of 3 header bytes) dropped");
      break;
    }
    const bool recover = !options_.strict;
    // Recovery: skip from a damaged record to the next valid one (NoteDamage tells the rows).
    auto skip = [&](const std::string& what) {
      const std::optional<std::size_t> next = Resync(pos + 1);
      NoteDamage(pos, next.value_or(n_), what);
      pos = next.value_or(n_);
    };
    if (d_[pos] != kHead1 || d_[pos + 1] != kHead2) {
      if (recover) {
        skip("no record header (A3 95)");
        continue;
      }
      return Bad(pos, "no record header (A3 95) here: the file is corrupt or not a DataFlash log");
    }
    const int type = d_[pos + 2];
    const auto it = layouts_.find(type);
    if (it == layouts_.end()) {
      if (recover) {
        skip("record of message type " + std::to_string(type) + " that no FMT defined");
        continue;
      }
      return Bad(pos, "record of message type " + std::to_string(type) + " that no FMT defined");
    }
    const Layout& l = it->second;
    const std::size_t len = static_cast<std::size_t>(l.fmt.length);
    if (len > n_ - pos) {
      if (recover) {
        if (const auto next = Resync(pos + 1)) {
          NoteDamage(pos, *next, l.fmt.name + " record of " + std::to_string(len) + " bytes runs past valid records");
          pos = *next;
          continue;
        }
      }
      out_.warnings.push_back(out_.source + ": byte " + std::to_string(pos) + ": truncated last record (" + l.fmt.name +
                              ", " + std::to_string(n_ - pos) + " of " + std::to_string(len) + " bytes) dropped");
      break;
    }
    // A record is taken only when a valid header (or the end of the file) follows it: a flipped
    // type byte naming another message of another length is not decoded as that message.
    if (recover && !HeaderAt(pos + len, type == kFmtType ? d_[pos + kHeaderBytes] : -1) && !DamagedHeaderAt(pos + len)) {
      skip(l.fmt.name + " record not followed by a record header");
      continue;
    }
    const std::uint8_t* p = d_ + pos + kHeaderBytes;
    ++out_.num_records;
    ++out_.message_counts[l.fmt.name];
    if (type == kFmtType) {
      if (auto e = AddFormat(pos, p)) {
        if (!recover) return *e;
        --out_.num_records;
        --out_.message_counts[l.fmt.name];
        skip(WithoutPlace(e->message));
        continue;
      }
    } else if (l.decodable && l.fmt.name == "PARM") {
      TakeParameter(l, p, pos);
    } else if (l.decodable && (l.fmt.name == "IMU" || l.fmt.name == "IMU2" || l.fmt.name == "IMU3")) {
      TakeImu(l, p);
    } else if (l.decodable && (l.fmt.name == "ARM" || l.fmt.name == "EV")) {
      TakeState(l, p);
    }
    pos += len;
    if (release_ && pos - released_ >= (std::size_t{64} << 20)) release_(released_ = pos);
  }
  for (auto& [instance, w] : windows_) FlushWindow(instance);
  if (const std::string w = DamageWarning(out_.source, out_.damage); !w.empty()) out_.warnings.push_back(w);
  std::sort(out_.imus.begin(), out_.imus.end(),
            [](const DataFlashImuSeries& a, const DataFlashImuSeries& b) { return a.instance < b.instance; });
  return std::move(out_);
}

std::optional<Error> Parser::AddFormat(std::size_t at, const std::uint8_t* p) {
  Layout l;
  l.fmt.type = p[0];
  l.fmt.length = p[1];
  l.fmt.name = Text(p + 2, 4);
  l.fmt.format = Text(p + 6, 16);
  l.fmt.labels = SplitComma(Text(p + 22, 64));
  if (l.fmt.type == kFmtType) {
    if (l.fmt.length != kFmtLength || l.fmt.format != "BBnNZ") {
      return Bad(at, "FMT redefines FMT as length " + std::to_string(l.fmt.length) + " format '" + l.fmt.format + "'");
    }
    out_.formats.push_back(l.fmt);
    return std::nullopt;
  }
  if (l.fmt.length < static_cast<int>(kHeaderBytes)) {
    return Bad(at, "FMT for '" + l.fmt.name + "' gives length " + std::to_string(l.fmt.length) + " < 3");
  }
  std::size_t size = 0;
  for (char c : l.fmt.format) {
    const std::size_t b = CharSize(c);
    if (b == 0) l.decodable = false;
    l.offsets.push_back(size);
    size += b;
  }
  if (l.decodable && size + kHeaderBytes != static_cast<std::size_t>(l.fmt.length)) {
    return Bad(at, "FMT for '" + l.fmt.name + "': format '" + l.fmt.format + "' needs " +
                       std::to_string(size + kHeaderBytes) + " bytes, its length says " + std::to_string(l.fmt.length));
  }
  out_.formats.push_back(l.fmt);
  layouts_[l.fmt.type] = std::move(l);
  return std::nullopt;
}

void Parser::TakeParameter(const Layout& l, const std::uint8_t* p, std::size_t at) {
  const auto name = FieldIndex(l, "Name");
  const auto value = FieldIndex(l, "Value");
  if (!name || !value || l.fmt.format[*name] != 'N') return;
  const auto v = Numeric(l.fmt.format[*value], p + l.offsets[*value]);
  if (!v) return;
  const std::string key = Text(p + l.offsets[*name], 16);
  const auto it = out_.parameters.find(key);
  if (it != out_.parameters.end() && it->second != *v && !imu_index_.empty()) {
    const auto t = FieldIndex(l, "TimeUS");
    const auto time_us = t ? Numeric(l.fmt.format[*t], p + l.offsets[*t]) : std::nullopt;
    out_.parameters_changed_during_imu.try_emplace(
        key, DataFlashContents::ParameterChange{at, time_us ? static_cast<std::uint64_t>(*time_us) : 0, it->second, *v});
  }
  out_.parameters[key] = *v;
}

void Parser::TakeState(const Layout& l, const std::uint8_t* p) {
  const bool arm = l.fmt.name == "ARM";
  auto get = [&](const char* label) -> std::optional<double> {
    const auto i = FieldIndex(l, label);
    return i ? Numeric(l.fmt.format[*i], p + l.offsets[*i]) : std::nullopt;
  };
  std::optional<double> time_us = get("TimeUS");
  if (!time_us) {
    if (const auto ms = get("TimeMS")) time_us = *ms * 1000.0;  // logs before TimeUS, as TakeImu
  }
  const auto value = get(arm ? "ArmState" : "Id");
  if (!time_us || !value) return;
  (arm ? out_.arm_states : out_.events).push_back({static_cast<std::uint64_t>(*time_us), static_cast<int>(*value)});
}

void Parser::TakeImu(const Layout& l, const std::uint8_t* p) {
  auto get = [&](const char* label) -> std::optional<double> {
    const auto i = FieldIndex(l, label);
    return i ? Numeric(l.fmt.format[*i], p + l.offsets[*i]) : std::nullopt;
  };
  const auto gx = get("GyrX"), gy = get("GyrY"), gz = get("GyrZ"), t = get("T");
  const auto ax = get("AccX"), ay = get("AccY"), az = get("AccZ");
  std::optional<double> time_us = get("TimeUS");
  if (!time_us) {
    if (const auto ms = get("TimeMS")) time_us = *ms * 1000.0;  // logs before TimeUS
  }
  if (!gx || !gy || !gz || !time_us) return;
  int instance = l.fmt.name == "IMU2" ? 1 : (l.fmt.name == "IMU3" ? 2 : 0);
  if (const auto i = get("I")) instance = static_cast<int>(*i);
  auto [it, added] = imu_index_.try_emplace(instance, out_.imus.size());
  if (added) {
    out_.imus.push_back({});
    out_.imus.back().instance = instance;
    out_.imus.back().message = l.fmt.name;
  }
  DataFlashImuSeries& s = out_.imus[it->second];
  ++s.records;
  const bool has_acc = ax && ay && az;
  const ImuRow row = {*time_us, *gx, *gy, *gz, has_acc ? *ax : 0.0, has_acc ? *ay : 0.0, has_acc ? *az : 0.0, t ? *t : 0.0};
  const std::uint64_t w = options_.average_window_us;
  if (w == 0) {
    PushImu(s, row, t.has_value(), has_acc);
    return;
  }
  Window& win = windows_[instance];
  const auto index = static_cast<std::uint64_t>(*time_us) / w;
  if (win.count > 0 && index != win.index) FlushWindow(instance);
  win.index = index;
  win.has_t = t.has_value();
  win.has_acc = has_acc;
  ++win.count;
  for (int k = 0; k < kRowFields; ++k) win.sum[k] += row[k];
}

void Parser::PushImu(DataFlashImuSeries& s, const ImuRow& r, bool has_t, bool has_acc) {
  s.time_us.push_back(static_cast<std::uint64_t>(std::llround(r[0])));
  if (options_.imu_instance && s.instance != *options_.imu_instance) return;  // counted only
  s.gyr_x_rad_s.push_back(r[1]);
  s.gyr_y_rad_s.push_back(r[2]);
  s.gyr_z_rad_s.push_back(r[3]);
  if (has_acc) {
    s.acc_x_m_s2.push_back(r[4]);
    s.acc_y_m_s2.push_back(r[5]);
    s.acc_z_m_s2.push_back(r[6]);
  }
  if (has_t) s.temp_c.push_back(r[7]);
}

void Parser::FlushWindow(int instance) {
  Window& w = windows_[instance];
  if (w.count == 0) return;
  ImuRow mean = w.sum;
  for (double& v : mean) v /= static_cast<double>(w.count);
  PushImu(out_.imus[imu_index_.at(instance)], mean, w.has_t, w.has_acc);
  w.count = 0;
  w.sum = ImuRow{};
}

}  // namespace

bool HasDataFlashMagic(const std::uint8_t* data, std::size_t size) {
  return size >= 3 && data[0] == kHead1 && data[1] == kHead2 && data[2] == kFmtType;
}

Result<DataFlashContents> ParseDataFlash(const std::uint8_t* data, std::size_t size, const std::string& source,
                                         const DataFlashReadOptions& options) {
  return Parser(data, size, source, options, nullptr).Run();
}

Result<DataFlashContents> ReadDataFlash(const std::string& path, const DataFlashReadOptions& options) {
  if (Result<MappedFile> map = MappedFile::Open(path); map.ok()) {
    MappedFile* m = &*map;
    return Parser(m->data(), m->size(), path, options, [m](std::size_t offset) { m->ReleaseBefore(offset); }).Run();
  }
  Result<std::string> bytes = ReadFileBytes(path);
  if (!bytes.ok()) return bytes.error();
  return ParseDataFlash(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size(), path, options);
}

std::string DataFlashContents::BriefReport() const {
  std::string s = source + ": DataFlash, " + std::to_string(num_records) + " records, " +
                  std::to_string(formats.size()) + " FMT, " + std::to_string(parameters.size()) + " parameters, " +
                  std::to_string(imus.size()) + " IMU instances with data";
  return s;
}

}  // namespace gyrocomp
