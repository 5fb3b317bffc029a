// ROS bags as IMU tables (include/gyrocomp/io/bag.h ReadBagImu): the collector that decodes the
// sensor_msgs/Imu topic and joins the nearest sensor_msgs/Temperature sample to each row. The
// bag formats themselves are streamed by StreamBag (bag.cc).
#include "gyrocomp/io/bag.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

#include "gyrocomp/core/format.h"
#include "gyrocomp/io/cdr.h"

namespace gyrocomp {

namespace {

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

}  // namespace

Result<BagImuTable> ReadBagImu(const std::string& path, const BagReadOptions& options) {
  ImuCollector collector(path, options);
  if (auto e = StreamBag(path, options, &collector)) return *e;
  return collector.Finish(DetectBagFormat(path));
}

}  // namespace gyrocomp
