// What a flight log or a ROS bag holds (gyrocomp/io/inspect.h): the listing `gyrocomp inspect`
// prints and writes as JSON.
#include "gyrocomp/io/inspect.h"

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "gyrocomp/io/bag.h"
#include "gyrocomp/io/dataflash.h"
#include "gyrocomp/io/ulog.h"

namespace gyrocomp {
namespace {

// One gyro instance: rows, time span, mean sample rate, temperature range.
nlohmann::json InstanceJson(const std::string& source, int instance, const std::vector<std::uint64_t>& time_us,
                            const std::vector<double>& temp_c, std::optional<std::uint32_t> device_id) {
  nlohmann::json j;
  j["source"] = source;
  j["instance"] = instance;
  j["rows"] = time_us.size();
  j["device_id"] = device_id ? nlohmann::json(*device_id) : nlohmann::json();
  const double span = time_us.size() > 1 ? static_cast<double>(time_us.back() - time_us.front()) / 1e6 : 0.0;
  j["time_span_s"] = span;
  j["sample_rate_hz"] = span > 0 ? nlohmann::json(static_cast<double>(time_us.size() - 1) / span) : nlohmann::json();
  if (temp_c.empty()) {
    j["temp_range_c"] = nlohmann::json();
  } else {
    const auto [lo, hi] = std::minmax_element(temp_c.begin(), temp_c.end());
    j["temp_range_c"] = {*lo, *hi};
  }
  return j;
}

nlohmann::json CompensationJson(const std::map<std::string, double>& params, const std::string& prefix) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, value] : params) {
    if (name.rfind(prefix, 0) == 0 && (name.find("ENABLE") != std::string::npos || name.find("_ID") != std::string::npos)) {
      j[name] = value;
    }
  }
  return j;
}

nlohmann::json InspectULog(const ULogContents& log) {
  nlohmann::json j;
  j["format"] = "ulog";
  j["ulog_version"] = log.version;
  nlohmann::json info = nlohmann::json::object();  // the short ones: sys_name, ver_hw, ... (not perf dumps)
  for (const auto& [key, value] : log.info) {
    if (value.size() <= 64 && key.rfind("perf_", 0) != 0) info[key] = value;
  }
  j["info"] = info;
  nlohmann::json topics = nlohmann::json::array();
  for (const ULogTopic& t : log.topics) topics.push_back({{"name", t.name}, {"multi_id", t.multi_id}, {"rows", t.rows}});
  j["topics"] = topics;
  nlohmann::json gyros = nlohmann::json::array();
  for (const auto* list : {&log.gyros, &log.combined}) {
    for (const ULogGyroSeries& g : *list) {
      gyros.push_back(InstanceJson(g.topic, g.multi_id, g.timestamp_us, g.temperature_c, g.device_id));
    }
  }
  j["gyro_instances"] = gyros;
  // Every sensor kind and instance: gyro (sensor_gyro; sensor_combined when it is the only one),
  // accel (sensor_accel), baro (sensor_baro), each with its device_id as logged.
  nlohmann::json sensors = nlohmann::json::array();
  for (nlohmann::json g : gyros) {
    g["type"] = "gyro";
    sensors.push_back(g);
  }
  for (const ULogAccelSeries& a : log.accels) {
    nlohmann::json s = InstanceJson("sensor_accel", a.multi_id, a.timestamp_us, a.temperature_c, a.device_id);
    s["type"] = "accel";
    sensors.push_back(s);
  }
  for (const ULogBaroSeries& b : log.baros) {
    nlohmann::json s = InstanceJson("sensor_baro", b.multi_id, b.timestamp_us, b.temperature_c, b.device_id);
    s["type"] = "baro";
    sensors.push_back(s);
  }
  j["sensors"] = sensors;
  j["damage"] = DamageJson(log.damage);
  std::size_t dropout_ms = 0;
  for (const ULogDropout& d : log.dropouts) dropout_ms += d.duration_ms;
  j["dropouts"] = {{"count", log.dropouts.size()}, {"total_ms", dropout_ms}};
  j["appended_segments"] = log.appended_offsets.size();
  // PX4 thermal compensation: TC_G_ENABLE and the TC_G{i}_ID device ids it applies to.
  j["compensation_parameters"] = CompensationJson(log.parameters, "TC_G");
  j["warnings"] = log.warnings;
  return j;
}

nlohmann::json InspectDataFlash(const DataFlashContents& log) {
  nlohmann::json j;
  j["format"] = "dataflash";
  j["messages"] = log.message_counts;
  // Device ids: ArduPilot's INS_GYR_ID, INS_GYR2_ID, INS_GYR3_ID (INS_ACC*_ID for accels) hold
  // the id of IMU instance 0, 1, 2 (AP_InertialSensor::var_info); BARO{n}_DEVID of baro n-1.
  auto param_id = [&](const std::string& name) -> std::optional<std::uint32_t> {
    const auto it = log.parameters.find(name);
    if (it == log.parameters.end() || it->second <= 0) return std::nullopt;
    return static_cast<std::uint32_t>(it->second);
  };
  auto ins_id = [&](const char* kind, int instance) {
    return param_id(std::string("INS_") + kind + (instance == 0 ? "" : std::to_string(instance + 1)) + "_ID");
  };
  nlohmann::json gyros = nlohmann::json::array();
  nlohmann::json sensors = nlohmann::json::array();
  for (const DataFlashImuSeries& s : log.imus) {
    nlohmann::json g = InstanceJson(s.message, s.instance, s.time_us, s.temp_c, ins_id("GYR", s.instance));
    gyros.push_back(g);
    g["type"] = "gyro";
    sensors.push_back(g);
    if (!s.acc_x_m_s2.empty() || s.gyr_x_rad_s.empty()) {
      nlohmann::json a = InstanceJson(s.message, s.instance, s.time_us, s.temp_c, ins_id("ACC", s.instance));
      a["type"] = "accel";
      sensors.push_back(a);
    }
  }
  // Barometers: the BARO message's records (the reader keeps no baro rows) and BARO{n}_DEVID.
  for (const char* name : {"BARO", "BAR2", "BAR3"}) {
    const auto it = log.message_counts.find(name);
    if (it == log.message_counts.end() || it->second == 0) continue;
    const int n = name[3] == 'O' ? 0 : name[3] - '1';
    sensors.push_back({{"type", "baro"}, {"source", name}, {"instance", n}, {"rows", it->second},
                       {"device_id", param_id("BARO" + std::to_string(n + 1) + "_DEVID")
                                         ? nlohmann::json(*param_id("BARO" + std::to_string(n + 1) + "_DEVID"))
                                         : nlohmann::json()},
                       {"sample_rate_hz", nullptr}, {"temp_range_c", nullptr}, {"time_span_s", nullptr}});
  }
  j["gyro_instances"] = gyros;
  j["sensors"] = sensors;
  j["damage"] = DamageJson(log.damage);
  // ArduPilot thermal calibration: INS_TCAL{n}_ENABLE for IMU n-1.
  j["compensation_parameters"] = CompensationJson(log.parameters, "INS_TCAL");
  j["warnings"] = log.warnings;
  return j;
}

// A ROS bag: every topic with its type, encoding, message count and mean rate (by
// receive time); the IMU topics are the ones `--topic` chooses from.
nlohmann::json InspectBag(const BagListing& bag) {
  nlohmann::json j;
  j["format"] = std::string(BagFormatName(bag.format));
  nlohmann::json topics = nlohmann::json::array();
  for (const BagTopicInfo& t : bag.topics) {
    const std::optional<double> rate = t.RateHz();
    topics.push_back({{"topic", t.topic}, {"type", t.type}, {"encoding", t.encoding}, {"messages", t.messages},
                      {"rate_hz", rate ? nlohmann::json(*rate) : nlohmann::json()},
                      {"imu", t.type == "sensor_msgs/msg/Imu" || t.type == "sensor_msgs/Imu"}});
  }
  j["topics"] = topics;
  j["damage"] = DamageJson(bag.damage);
  j["warnings"] = bag.warnings;
  return j;
}

LogSensorInstance SensorFromJson(const nlohmann::json& s) {
  LogSensorInstance x;
  x.type = s["type"].get<std::string>();
  x.source = s["source"].get<std::string>();
  x.instance = s["instance"].get<int>();
  x.rows = s["rows"].get<std::size_t>();
  if (!s["device_id"].is_null()) x.device_id = s["device_id"].get<std::uint32_t>();
  if (!s["time_span_s"].is_null()) x.time_span_s = s["time_span_s"].get<double>();
  if (!s["sample_rate_hz"].is_null()) x.sample_rate_hz = s["sample_rate_hz"].get<double>();
  if (!s["temp_range_c"].is_null()) x.temp_range_c = {s["temp_range_c"][0].get<double>(), s["temp_range_c"][1].get<double>()};
  return x;
}

}  // namespace

bool InspectOptions::IsValid(std::string* /*error*/) const { return true; }

Result<LogInventory> InspectLog(const std::string& path, const InspectOptions& options) {
  LogInventory inv;
  inv.format = DetectLogFormat(path);
  switch (inv.format) {
    case LogFormat::kULog: {
      ULogReadOptions o;
      o.strict = options.strict;
      Result<ULogContents> log = ReadULog(path, o);
      if (!log.ok()) return log.error();
      inv.listing = InspectULog(*log);
      inv.damage = log->damage;
      inv.warnings = log->warnings;
      break;
    }
    case LogFormat::kDataFlash: {
      DataFlashReadOptions o;
      o.strict = options.strict;
      Result<DataFlashContents> log = ReadDataFlash(path, o);
      if (!log.ok()) return log.error();
      inv.listing = InspectDataFlash(*log);
      inv.damage = log->damage;
      inv.warnings = log->warnings;
      break;
    }
    case LogFormat::kRosBag: {
      BagReadOptions o;
      o.strict = options.strict;
      Result<BagListing> bag = ListBag(path, o);
      if (!bag.ok()) return bag.error();
      inv.listing = InspectBag(*bag);
      inv.damage = bag->damage;
      inv.warnings = bag->warnings;
      break;
    }
    default:
      return InvalidInput(path + ": not a PX4 ULog, ArduPilot DataFlash log or ROS bag (by its first bytes); inspect "
                                 "reads flight-controller logs and bags");
  }
  if (inv.listing.contains("sensors"))
    for (const auto& s : inv.listing["sensors"]) inv.sensors.push_back(SensorFromJson(s));
  return inv;
}

std::string LogInventory::BriefReport() const {
  std::string s = listing.value("format", std::string("?")) + ": ";
  if (!listing.contains("sensors")) {
    std::size_t imu = 0;
    for (const auto& t : listing["topics"]) imu += t["imu"].get<bool>() ? 1 : 0;
    s += std::to_string(listing["topics"].size()) + " topics, " + std::to_string(imu) + " IMU";
  } else {
    std::map<std::string, int> by_type;
    for (const LogSensorInstance& x : sensors) ++by_type[x.type];
    s += std::to_string(sensors.size()) + " sensor instance" + (sensors.size() == 1 ? "" : "s");
    std::string parts;
    for (const char* t : {"gyro", "accel", "baro"})
      if (by_type.count(t)) parts += (parts.empty() ? "" : ", ") + std::string(t) + " " + std::to_string(by_type[t]);
    if (!parts.empty()) s += " (" + parts + ")";
  }
  s += damage.empty() ? ", no damage" : ", " + std::to_string(damage.size()) + " damaged range" + (damage.size() == 1 ? "" : "s");
  if (!warnings.empty()) s += ", " + std::to_string(warnings.size()) + " warning" + (warnings.size() == 1 ? "" : "s");
  return s;
}

}  // namespace gyrocomp
