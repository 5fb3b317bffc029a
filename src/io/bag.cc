// ROS bags as IMU tables (include/gyrocomp/io/bag.h): format detection, ROS 2 bag folders, the
// IMU / temperature collector and the topic listing.
#include "gyrocomp/io/bag.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <set>
#include <sstream>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "gyrocomp/core/format.h"
#include "gyrocomp/io/cdr.h"
#include "bag_bytes.h"

namespace gyrocomp {

namespace fs = std::filesystem;

namespace {

// MCAP spec "Magic"; sqlite3 fileformat2.html "1.3 The Database Header" (offset 0, 16 bytes);
// ROS wiki Bags/Format/2.0 "Version".
constexpr std::uint8_t kMcapMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr char kSqliteMagic[16] = "SQLite format 3";  // with its NUL: 16 bytes
constexpr char kRos1Magic[] = "#ROSBAG V2.0\n";

BagFormat DetectHead(const std::uint8_t* head, std::size_t n) {
  if (n >= 8 && std::memcmp(head, kMcapMagic, 8) == 0) return BagFormat::kMcap;
  if (n >= 16 && std::memcmp(head, kSqliteMagic, 16) == 0) return BagFormat::kRos2Sqlite;
  if (n >= 13 && std::memcmp(head, kRos1Magic, 13) == 0) return BagFormat::kRos1;
  return BagFormat::kNone;
}

// By the first 16 bytes; a Zstandard file (rosbag2 per-file compression) by the first 16 bytes
// it decompresses to.
BagFormat DetectFile(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return BagFormat::kNone;
  std::ifstream in(path, std::ios::binary);
  std::uint8_t head[16] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  const auto n = static_cast<std::size_t>(in.gcount());
  if (!bag_internal::HasZstdMagic(head, n)) return DetectHead(head, n);
  in.clear();
  in.seekg(0);
  std::ostringstream inner;
  if (!bag_internal::DecompressZstdFile(in, inner, sizeof head, true).empty()) return BagFormat::kNone;
  const std::string h = inner.str();
  return DetectHead(reinterpret_cast<const std::uint8_t*>(h.data()), h.size());
}

bool IsZstdFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::uint8_t head[4] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  return bag_internal::HasZstdMagic(head, static_cast<std::size_t>(in.gcount()));
}

// The storage files of a ROS 2 bag folder: metadata.yaml's rosbag2_bagfile_information.
// relative_file_paths list (rosbag2_storage/src/rosbag2_storage/metadata_io.cpp writes it as a
// YAML block sequence), else the folder's *.mcap / *.db3 in name order.
std::vector<std::string> FolderFiles(const std::string& dir) {
  std::vector<std::string> files;
  std::ifstream meta(dir + "/metadata.yaml");
  std::string line;
  bool in_list = false;
  while (std::getline(meta, line)) {
    const std::size_t b = line.find_first_not_of(" \t");
    if (b == std::string::npos) continue;
    const std::string t = line.substr(b);
    if (t.rfind("relative_file_paths:", 0) == 0) {
      in_list = true;
      continue;
    }
    if (!in_list) continue;
    if (t.rfind("- ", 0) != 0) break;
    std::string name = t.substr(2);
    while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
    if (name.size() >= 2 && (name.front() == '"' || name.front() == '\'')) name = name.substr(1, name.size() - 2);
    files.push_back(dir + "/" + name);
  }
  if (!files.empty()) return files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string ext = e.path().extension().string();
    const std::string stem_ext = e.path().stem().extension().string();
    if (ext == ".mcap" || ext == ".db3" || (ext == ".zstd" && (stem_ext == ".mcap" || stem_ext == ".db3"))) {
      files.push_back(e.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// metadata.yaml's rosbag2_bagfile_information.compression_mode ("", FILE or MESSAGE;
// rosbag2_storage metadata_io.cpp), unquoted.
std::string CompressionMode(const std::string& dir) {
  std::ifstream meta(dir + "/metadata.yaml");
  std::string line;
  while (std::getline(meta, line)) {
    const std::size_t at = line.find("compression_mode:");
    if (at == std::string::npos) continue;
    std::string v = line.substr(at + 17);
    v.erase(std::remove_if(v.begin(), v.end(), [](char c) { return c == ' ' || c == '"' || c == '\'' || c == '\r'; }), v.end());
    return v;
  }
  return "";
}

bool IsFolderBag(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec) && fs::is_regular_file(path + "/metadata.yaml", ec);
}

// Channel ids of the k-th file of a folder are moved to (k << 32) + id, so files with their own
// numbering do not collide.
class OffsetVisitor : public BagVisitor {
 public:
  OffsetVisitor(BagVisitor* inner, std::uint64_t offset) : inner_(inner), offset_(offset) {}
  std::optional<Error> OnChannel(const BagChannel& c) override {
    BagChannel moved = c;
    moved.id += offset_;
    return inner_->OnChannel(moved);
  }
  bool Wants(std::uint64_t ch) const override { return inner_->Wants(ch + offset_); }
  std::optional<Error> OnMessage(const BagMessage& m) override {
    BagMessage moved = m;
    moved.channel += offset_;
    return inner_->OnMessage(moved);
  }
  void Count(std::uint64_t ch, std::uint64_t t) override { inner_->Count(ch + offset_, t); }
  void OnDamage(const LogDamage& d) override { inner_->OnDamage(d); }

 private:
  BagVisitor* inner_;
  std::uint64_t offset_;
};

std::optional<Error> StreamFile(const std::string& path, const BagReadOptions& options, BagVisitor* visitor);

// A temporary file removed (with sqlite3's side files) when it goes out of scope.
class TempFile {
 public:
  TempFile() {
    std::error_code ec;
    std::string pattern = (fs::temp_directory_path(ec) / "gyrocomp_bag_XXXXXX").string();
    const int fd = ::mkstemp(pattern.data());
    if (fd >= 0) {
      ::close(fd);
      path_ = pattern;
    }
  }
  ~TempFile() {
    if (path_.empty()) return;
    for (const char* side : {"", "-journal", "-wal", "-shm"}) std::remove((path_ + side).c_str());
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// rosbag2 per-file compression (rosbag2_compression, compression_mode FILE, format zstd): the
// storage file is Zstandard-compressed whole. sqlite3 needs a file and the MCAP reader seeks, so
// the file is stream-decompressed (bounded buffers) into a temporary file ($TMPDIR), read there
// and removed; errors name the compressed file.
std::optional<Error> StreamZstdFile(const std::string& path, const BagReadOptions& options, BagVisitor* visitor) {
  TempFile temp;
  if (temp.path().empty()) return IoError(path + ": cannot create a temporary file to decompress into");
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) return IoError(path + ": cannot open");
    std::ofstream out(temp.path(), std::ios::binary | std::ios::trunc);
    // Never more than the free space of the temporary folder (less 64 MiB for everyone else).
    std::error_code ec;
    const fs::space_info space = fs::space(fs::path(temp.path()).parent_path(), ec);
    const std::uint64_t margin = std::uint64_t{64} << 20;
    const std::uint64_t free_bytes = ec ? UINT64_MAX : (space.available > margin ? space.available - margin : 0);
    const std::uint64_t limit = std::min(options.max_decompressed_file_bytes, free_bytes);
    std::string why = bag_internal::DecompressZstdFile(in, out, limit);
    if (!why.empty() && limit < options.max_decompressed_file_bytes && why.find("compression bomb") != std::string::npos) {
      why = "decompresses to more than the " + std::to_string(limit) + " bytes free in " +
            fs::path(temp.path()).parent_path().string() + " (set TMPDIR to a folder with room)";
    }
    if (!why.empty()) return InvalidInput(path + ": " + why);
    out.close();
    if (!out) return IoError(path + ": cannot write the decompressed file " + temp.path() + " (disk full?)");
  }
  if (DetectFile(temp.path()) == BagFormat::kNone || IsZstdFile(temp.path())) {
    return InvalidInput(path + ": decompressed byte 0: not an MCAP, ROS 2 sqlite3 or ROS 1 v2.0 bag (by its first bytes)");
  }
  std::optional<Error> e = StreamFile(temp.path(), options, visitor);
  if (e) {
    // The reader named the temporary file: name the bag instead.
    const std::string decompressed = path + " (decompressed)";
    for (std::size_t at = e->message.find(temp.path()); at != std::string::npos;
         at = e->message.find(temp.path(), at + decompressed.size())) {
      e->message.replace(at, temp.path().size(), decompressed);
    }
  }
  return e;
}

std::optional<Error> StreamFile(const std::string& path, const BagReadOptions& options, BagVisitor* visitor) {
  if (IsZstdFile(path)) return StreamZstdFile(path, options, visitor);
  const BagFormat format = DetectFile(path);
  if (format == BagFormat::kRos2Sqlite) return StreamRos2Sqlite(path, options, visitor);
  if (format == BagFormat::kNone) {
    return InvalidInput(path + ": byte 0: not an MCAP, ROS 2 sqlite3 or ROS 1 v2.0 bag (by its first bytes)");
  }
  if (format == BagFormat::kRos1) return StreamRos1BagFile(path, options, visitor);
  std::ifstream in(path, std::ios::binary);
  if (!in) return IoError(path + ": cannot open");
  return StreamMcap(in, path, options, visitor);
}

bool IsImuType(const std::string& t) { return t == "sensor_msgs/msg/Imu" || t == "sensor_msgs/Imu"; }
bool IsTemperatureType(const std::string& t) {
  return t == "sensor_msgs/msg/Temperature" || t == "sensor_msgs/Temperature";
}

std::string Namespace(const std::string& topic) {
  const std::size_t slash = topic.rfind('/');
  return slash == std::string::npos ? "" : topic.substr(0, slash);
}

// Seconds from integer nanoseconds, whole seconds and fraction converted apart.
double Seconds(std::int64_t ns) {
  const std::int64_t s = ns / 1000000000, f = ns % 1000000000;
  return static_cast<double>(s) + static_cast<double>(f) / 1e9;
}

// The rows of one IMU topic (all channels publishing on it).
struct ImuRows {
  std::string topic, type, encoding;
  std::vector<std::int64_t> time_ns;
  std::vector<double> gyro[3], accel[3];
  // Room for `more` rows on top of those held (the index's count: the columns then grow once,
  // with no copy and no shrink at the end). Address space only: nothing is touched.
  void Reserve(std::uint64_t more) {
    const std::size_t n = time_ns.size() + static_cast<std::size_t>(more);
    time_ns.reserve(n);
    for (int k = 0; k < 3; ++k) {
      gyro[k].reserve(n);
      accel[k].reserve(n);
    }
  }
};

struct TemperatureRows {
  std::string topic;
  std::vector<std::int64_t> time_ns;
  std::vector<double> temp_c;
};

class ImuCollector : public BagVisitor {
 public:
  ImuCollector(const std::string& source, const BagReadOptions& options) : source_(source), options_(options) {}

  std::optional<Error> OnChannel(const BagChannel& c) override {
    const bool imu = IsImuType(c.type);
    if (imu) all_imu_topics_.insert(c.topic);
    if (options_.topic && c.topic == *options_.topic && !imu) {
      return InvalidInput(source_ + ": topic " + c.topic + " has type " + (c.type.empty() ? "(no schema)" : c.type) +
                          ", not sensor_msgs/Imu");
    }
    if (imu && (!options_.topic || c.topic == *options_.topic)) {
      if (c.encoding != "cdr" && c.encoding != "ros1") {
        return InvalidInput(source_ + ": topic " + c.topic + ": message encoding '" + c.encoding +
                            "' (only cdr and ros1 are decoded)");
      }
      auto [it, added] = imu_index_.emplace(c.topic, imus_.size());
      if (added) imus_.push_back(ImuRows{c.topic, c.type, c.encoding, {}, {}, {}});
      if (c.expected_messages) imus_[it->second].Reserve(*c.expected_messages);
      channels_[c.id] = {false, it->second, c.encoding == "cdr"};
    } else if (IsTemperatureType(c.type) && (c.encoding == "cdr" || c.encoding == "ros1")) {
      auto [it, added] = temp_index_.emplace(c.topic, temps_.size());
      if (added) temps_.push_back(TemperatureRows{c.topic, {}, {}});
      channels_[c.id] = {true, it->second, c.encoding == "cdr"};
    }
    return std::nullopt;
  }
  bool Wants(std::uint64_t ch) const override { return channels_.count(ch) != 0; }
  std::optional<Error> OnMessage(const BagMessage& m) override {
    const Target& t = channels_.at(m.channel);
    return t.temperature ? AddTemperature(t, m) : AddImu(t, m);
  }

  void OnDamage(const LogDamage& d) override { damage_.push_back(d); }

  Result<BagImuTable> Finish(BagFormat format);

 private:
  Result<BagImuTable> FinishTable(BagFormat format);
  struct Target {
    bool temperature = false;
    std::size_t index = 0;
    bool cdr = true;
  };
  Error DecodeFailed(const BagMessage& m, const std::string& topic, const DecodeError& e) const {
    return InvalidInput(source_ + ": " + m.where.ToString() + ": topic " + topic + ": message byte " + std::to_string(e.offset) +
                        " of " + std::to_string(m.size) + ": " + e.what);
  }
  std::int64_t Time(std::int64_t stamp_ns, std::uint64_t receive_ns) const {
    return options_.time == BagTimeSource::kHeader ? stamp_ns : static_cast<std::int64_t>(receive_ns);
  }
  std::optional<Error> AddImu(const Target& t, const BagMessage& m) {
    ImuRows& rows = imus_[t.index];
    ImuMessage msg;
    const auto e = t.cdr ? DecodeCdrImu(m.data, m.size, &msg) : DecodeRos1Imu(m.data, m.size, &msg);
    if (e) return DecodeFailed(m, rows.topic, *e);
    rows.time_ns.push_back(Time(msg.StampNs(), m.receive_time_ns));
    for (int k = 0; k < 3; ++k) {
      rows.gyro[k].push_back(msg.angular_velocity_rad_s[k]);
      rows.accel[k].push_back(msg.linear_acceleration_m_s2[k]);
    }
    return std::nullopt;
  }
  std::optional<Error> AddTemperature(const Target& t, const BagMessage& m) {
    TemperatureRows& rows = temps_[t.index];
    TemperatureMessage msg;
    const auto e = t.cdr ? DecodeCdrTemperature(m.data, m.size, &msg) : DecodeRos1Temperature(m.data, m.size, &msg);
    if (e) return DecodeFailed(m, rows.topic, *e);
    rows.time_ns.push_back(Time(msg.StampNs(), m.receive_time_ns));
    rows.temp_c.push_back(msg.temperature_c);
    return std::nullopt;
  }
  const TemperatureRows* PickTemperature(const std::string& imu_topic, std::vector<std::string>* warnings) const;

  const std::string& source_;
  const BagReadOptions& options_;
  std::map<std::uint64_t, Target> channels_;
  std::map<std::string, std::size_t> imu_index_, temp_index_;
  std::set<std::string> all_imu_topics_;  // every sensor_msgs/Imu topic, selected or not
  std::vector<ImuRows> imus_;
  std::vector<TemperatureRows> temps_;
  std::vector<LogDamage> damage_;
};

// The temperature topic to join: the only one, or the only one in the IMU topic's namespace.
const TemperatureRows* ImuCollector::PickTemperature(const std::string& imu_topic, std::vector<std::string>* warnings) const {
  std::vector<const TemperatureRows*> with_rows;
  for (const TemperatureRows& t : temps_) {
    if (!t.time_ns.empty()) with_rows.push_back(&t);
  }
  if (with_rows.size() == 1) return with_rows.front();
  if (with_rows.empty()) return nullptr;
  std::vector<const TemperatureRows*> same_ns;
  std::string names;
  for (const TemperatureRows* t : with_rows) {
    if (Namespace(t->topic) == Namespace(imu_topic)) same_ns.push_back(t);
    names += (names.empty() ? "" : ", ") + t->topic;
  }
  if (same_ns.size() == 1) return same_ns.front();
  warnings->push_back(source_ + ": several sensor_msgs/Temperature topics (" + names + "), none alone in " +
                      imu_topic + "'s namespace: no temperature column");
  return nullptr;
}

// Sorts `v` by `order` (a permutation), in place through one temporary.
template <typename T>
void Permute(std::vector<T>* v, const std::vector<std::size_t>& order) {
  std::vector<T> out(v->size());
  for (std::size_t i = 0; i < order.size(); ++i) out[i] = (*v)[order[i]];
  *v = std::move(out);
}

// |a - b| for any two stamps (a 2^63 ns apart from b does not overflow: the unsigned difference
// of two's-complement values is exact below 2^64).
std::uint64_t Distance(std::int64_t a, std::int64_t b) {
  const auto ua = static_cast<std::uint64_t>(a), ub = static_cast<std::uint64_t>(b);
  return a >= b ? ua - ub : ub - ua;
}

// Nearest temperature sample (by time) for each IMU time; temperature times sorted.
std::vector<double> JoinNearest(const std::vector<std::int64_t>& t_ns, const TemperatureRows& temp) {
  std::vector<std::size_t> order(temp.time_ns.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return temp.time_ns[a] < temp.time_ns[b]; });
  std::vector<std::int64_t> tt(order.size());
  std::vector<double> tv(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    tt[i] = temp.time_ns[order[i]];
    tv[i] = temp.temp_c[order[i]];
  }
  std::vector<double> out(t_ns.size());
  for (std::size_t i = 0; i < t_ns.size(); ++i) {
    const auto it = std::lower_bound(tt.begin(), tt.end(), t_ns[i]);
    std::size_t j = static_cast<std::size_t>(it - tt.begin());
    if (j == tt.size() || (j > 0 && Distance(t_ns[i], tt[j - 1]) <= Distance(tt[j], t_ns[i]))) j = j == 0 ? 0 : j - 1;
    out[i] = tv[j];
  }
  return out;
}

// A bag that cannot give a table says so with its damage, which may be why (a lost chunk held
// the topic's messages or its connection record).
Result<BagImuTable> ImuCollector::Finish(BagFormat format) {
  const std::string damage = damage_.empty() ? "" : "; " + DamageWarning(source_, damage_);
  Result<BagImuTable> out = FinishTable(format);
  if (!out.ok() && !damage.empty()) return Error{out.error().kind, out.error().message + damage};
  return out;
}

Result<BagImuTable> ImuCollector::FinishTable(BagFormat format) {
  BagImuTable out;
  out.format = format;
  if (!damage_.empty()) out.warnings.push_back(DamageWarning(source_, damage_));
  out.damage = std::move(damage_);
  if (options_.topic && imu_index_.count(*options_.topic) == 0) {
    std::string names;
    for (const std::string& t : all_imu_topics_) names += (names.empty() ? "" : ", ") + t;
    return InvalidInput(source_ + ": no sensor_msgs/Imu topic " + *options_.topic + " in the bag" +
                        (names.empty() ? std::string(" (it has no sensor_msgs/Imu topic; `gyrocomp inspect` lists its topics)")
                                       : std::string("; IMU topics: ") + names));
  }
  if (imus_.empty()) {
    return InvalidInput(source_ + ": no sensor_msgs/Imu topic in the bag (`gyrocomp inspect -i " + source_ + "` lists its topics)");
  }
  if (imus_.size() > 1) {
    std::string names;
    for (const ImuRows& r : imus_) names += (names.empty() ? "" : ", ") + r.topic + " (" + std::to_string(r.time_ns.size()) + " messages)";
    return InvalidInput(source_ + ": " + std::to_string(imus_.size()) + " sensor_msgs/Imu topics: " + names +
                        "; choose one with --topic NAME");
  }
  ImuRows& rows = imus_.front();
  if (rows.time_ns.empty()) return InvalidInput(source_ + ": topic " + rows.topic + " has no messages");
  // Drivers that do not stamp their messages leave header.stamp at 0 (or one constant).
  if (options_.time == BagTimeSource::kHeader && rows.time_ns.size() > 1 &&
      std::all_of(rows.time_ns.begin(), rows.time_ns.end(), [&](std::int64_t t) { return t == rows.time_ns.front(); })) {
    return InvalidInput(source_ + ": topic " + rows.topic + ": header.stamp is " + std::to_string(rows.time_ns.front()) +
                        " ns in all " + std::to_string(rows.time_ns.size()) +
                        " messages (the driver does not stamp them): use the bag's receive time, --time receive");
  }
  // Rows in time order (stable; chunks may overlap in time).
  if (!std::is_sorted(rows.time_ns.begin(), rows.time_ns.end())) {
    std::vector<std::size_t> order(rows.time_ns.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return rows.time_ns[a] < rows.time_ns[b]; });
    Permute(&rows.time_ns, order);
    for (int k = 0; k < 3; ++k) {
      Permute(&rows.gyro[k], order);
      Permute(&rows.accel[k], order);
    }
  }
  // push_back left up to twice the rows' capacity in each column; the table keeps these vectors.
  for (int k = 0; k < 3; ++k) {
    rows.gyro[k].shrink_to_fit();
    rows.accel[k].shrink_to_fit();
  }
  const TemperatureRows* temp = PickTemperature(rows.topic, &out.warnings);
  std::vector<double> time_s(rows.time_ns.size());
  for (std::size_t i = 0; i < time_s.size(); ++i) time_s[i] = Seconds(rows.time_ns[i]);
  out.topic = rows.topic;
  out.table.source = source_ + "[" + rows.topic + "]";
  out.table.Add(kBagTimeCol, std::move(time_s));
  for (int k = 0; k < 3; ++k) out.table.Add(kBagGyroCols[k], std::move(rows.gyro[k]));
  for (int k = 0; k < 3; ++k) out.table.Add(kBagAccelCols[k], std::move(rows.accel[k]));
  if (temp) {
    out.temperature_topic = temp->topic;
    out.table.Add(kBagTempCol, JoinNearest(rows.time_ns, *temp));
  }
  out.origin = std::string(format == BagFormat::kMcap ? "MCAP" : format == BagFormat::kRos1 ? "ROS 1 bag" : "rosbag2 sqlite3") +
               " " + rows.topic + " (" + rows.type + "), " +
               (options_.time == BagTimeSource::kHeader ? "header stamps" : "receive times") +
               (temp ? ", temperature from " + temp->topic : std::string(", no temperature topic"));
  // NaN / infinity in a message: refused with the row, as the flight-log reader does.
  for (std::size_t j = 1; j < out.table.columns.size(); ++j) {
    const std::vector<double>& c = out.table.columns[j];
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (std::isfinite(c[i])) continue;
      return InvalidInput(out.table.source + ": message " + std::to_string(i) + " (time_s " +
                          FormatNumber(out.table.columns[0][i]) + "): " + (std::isnan(c[i]) ? "NaN" : "infinity") +
                          " in " + out.table.names[j]);
    }
  }
  return out;
}

// Counts every message per channel, decodes none.
class Lister : public BagVisitor {
 public:
  std::optional<Error> OnChannel(const BagChannel& c) override {
    auto [it, added] = index_.emplace(c.topic, topics_.size());
    if (added) topics_.push_back(BagTopicInfo{c.topic, c.type, c.encoding});
    channel_topic_[c.id] = it->second;
    return std::nullopt;
  }
  bool Wants(std::uint64_t) const override { return false; }
  std::optional<Error> OnMessage(const BagMessage&) override { return std::nullopt; }
  void Count(std::uint64_t ch, std::uint64_t t) override {
    const auto it = channel_topic_.find(ch);
    if (it == channel_topic_.end()) return;
    BagTopicInfo& info = topics_[it->second];
    if (info.messages == 0 || t < info.first_receive_ns) info.first_receive_ns = t;
    if (info.messages == 0 || t > info.last_receive_ns) info.last_receive_ns = t;
    ++info.messages;
  }
  void OnDamage(const LogDamage& d) override { damage_.push_back(d); }
  std::vector<BagTopicInfo> topics_;
  std::vector<LogDamage> damage_;

 private:
  std::map<std::string, std::size_t> index_;
  std::map<std::uint64_t, std::size_t> channel_topic_;
};

}  // namespace

std::string BagPosition::ToString() const {
  if (message_id) return "message id " + std::to_string(*message_id);
  std::string s = "byte " + std::to_string(offset);
  if (chunk_byte) s += ": chunk byte " + std::to_string(*chunk_byte);
  return s;
}

std::string_view BagFormatName(BagFormat format) {
  switch (format) {
    case BagFormat::kMcap: return "mcap";
    case BagFormat::kRos2Sqlite: return "ros2-sqlite3";
    case BagFormat::kRos1: return "rosbag1";
    default: return "none";
  }
}

BagFormat DetectBagFormat(const std::string& path) {
  if (path == "-") return BagFormat::kNone;
  if (IsFolderBag(path)) {
    const std::vector<std::string> files = FolderFiles(path);
    return files.empty() ? BagFormat::kNone : DetectFile(files.front());
  }
  return DetectFile(path);
}

bool BagReadOptions::IsValid(std::string* error) const {
  if (max_chunk_bytes == 0) {
    *error = "BagReadOptions::max_chunk_bytes = 0: must be > 0";
    return false;
  }
  if (max_decompressed_file_bytes == 0) {
    *error = "BagReadOptions::max_decompressed_file_bytes = 0: must be > 0";
    return false;
  }
  if (topic && topic->empty()) {
    *error = "BagReadOptions::topic is empty: name a topic or leave it unset";
    return false;
  }
  return true;
}

std::optional<double> BagTopicInfo::RateHz() const {
  if (messages < 2 || last_receive_ns <= first_receive_ns) return std::nullopt;
  return static_cast<double>(messages - 1) / (static_cast<double>(last_receive_ns - first_receive_ns) / 1e9);
}

std::optional<Error> StreamBag(const std::string& path, const BagReadOptions& options, BagVisitor* visitor) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (!IsFolderBag(path)) return StreamFile(path, options, visitor);
  const std::vector<std::string> files = FolderFiles(path);
  if (files.empty()) return InvalidInput(path + ": a ROS 2 bag folder without .mcap or .db3 files");
  if (CompressionMode(path) == "MESSAGE") {
    return Unsupported(path + "/metadata.yaml: compression_mode MESSAGE (every message compressed on its own) is not "
                              "read; record with compression_mode FILE (read directly) or none");
  }
  for (std::size_t k = 0; k < files.size(); ++k) {
    OffsetVisitor moved(visitor, static_cast<std::uint64_t>(k) << 32);
    if (auto e = StreamFile(files[k], options, &moved)) return e;
  }
  return std::nullopt;
}

Result<BagListing> ListBag(const std::string& path, const BagReadOptions& options) {
  Lister lister;
  if (auto e = StreamBag(path, options, &lister)) return *e;
  BagListing out;
  out.source = path;
  out.format = DetectBagFormat(path);
  out.topics = std::move(lister.topics_);
  if (!lister.damage_.empty()) out.warnings.push_back(DamageWarning(path, lister.damage_));
  out.damage = std::move(lister.damage_);
  return out;
}

Result<BagImuTable> ReadBagImu(const std::string& path, const BagReadOptions& options) {
  ImuCollector collector(path, options);
  if (auto e = StreamBag(path, options, &collector)) return *e;
  return collector.Finish(DetectBagFormat(path));
}

}  // namespace gyrocomp
