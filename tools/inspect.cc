// gyrocomp inspect: what a PX4 ULog or ArduPilot DataFlash log holds (topics / messages, gyro
// instances with rows, sample rate and temperature range, compensation parameters found).
#include <algorithm>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "gyrocomp/io/bag.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/log_damage.h"
#include "table_printer.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kInspectName = "inspect";

struct InspectArgs {
  std::string input;
  std::string json_path;
  bool strict = false;
};

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

// "2 byte range(s), 120 bytes skipped (...)"; a rosbag2 .db3's damage is message id ranges
// (DamageJson), "1 message id range(s), 12 message ids skipped (...)".
std::string DamageSummary(const nlohmann::json& damage) {
  std::size_t byte_ranges = 0, bytes = 0, id_ranges = 0, ids = 0;
  for (const auto& d : damage) {
    if (d.contains("bytes")) {
      ++byte_ranges;
      bytes += d["bytes"].get<std::size_t>();
    } else {
      ++id_ranges;
      ids += d["messages"].get<std::size_t>();
    }
  }
  std::string s;
  if (byte_ranges) s = std::to_string(byte_ranges) + " byte range(s), " + std::to_string(bytes) + " bytes";
  if (id_ranges) {
    s += (s.empty() ? "" : "; ") + std::to_string(id_ranges) + " message id range(s), " + std::to_string(ids) + " message ids";
  }
  return s + " skipped (see the warning; every range in --json \"damage\")";
}

void PrintBag(const nlohmann::json& j) {
  std::cout << j["input"].get<std::string>() << ": " << j["format"].get<std::string>() << ", " << j["topics"].size()
            << " topics\n";
  std::vector<std::vector<std::string>> rows;
  for (const auto& t : j["topics"]) {
    rows.push_back({t["topic"].get<std::string>(), t["type"].get<std::string>(), t["encoding"].get<std::string>(),
                    std::to_string(t["messages"].get<std::size_t>()),
                    FormatNumber(t["rate_hz"].is_null() ? std::nullopt : std::optional<double>(t["rate_hz"].get<double>()))});
  }
  std::cout << FormatTable({"topic", "type", "encoding", "messages", "rate_hz"}, rows);
  if (!j["damage"].empty()) std::cout << "damage: " << DamageSummary(j["damage"]) << "\n";
  for (const auto& w : j["warnings"]) std::cout << "warning: " << w.get<std::string>() << "\n";
}

void PrintText(const nlohmann::json& j) {
  std::cout << j["input"].get<std::string>() << ": " << j["format"].get<std::string>() << "\n";
  if (j.contains("topics")) {
    std::cout << j["topics"].size() << " topic subscriptions; dropouts: " << j["dropouts"]["count"] << " ("
              << j["dropouts"]["total_ms"] << " ms); appended segments: " << j["appended_segments"] << "\n";
  } else {
    std::cout << j["messages"].size() << " message types\n";
  }
  std::vector<std::vector<std::string>> rows;
  for (const auto& g : j["sensors"]) {
    const auto& t = g["temp_range_c"];
    rows.push_back({g["type"].get<std::string>(), g["source"].get<std::string>(), std::to_string(g["instance"].get<int>()),
                    std::to_string(g["rows"].get<std::size_t>()),
                    g["device_id"].is_null() ? "-" : std::to_string(g["device_id"].get<std::uint32_t>()),
                    FormatNumber(g["sample_rate_hz"].is_null() ? std::nullopt : std::optional<double>(g["sample_rate_hz"].get<double>())),
                    t.is_null() ? "none" : FormatNumber(t[0].get<double>()) + " .. " + FormatNumber(t[1].get<double>())});
  }
  std::cout << FormatTable({"sensor", "source", "instance", "rows", "device_id", "rate_hz", "temp_c"}, rows);
  if (j["damage"].empty()) {
    std::cout << "damage: none found\n";
  } else {
    std::cout << "damage: " << DamageSummary(j["damage"]) << "\n";
  }
  std::cout << "compensation parameters: " << (j["compensation_parameters"].empty() ? "none found" : j["compensation_parameters"].dump())
            << "\n";
  for (const auto& w : j["warnings"]) std::cout << "warning: " << w.get<std::string>() << "\n";
}

int Run(const InspectArgs& a) {
  nlohmann::json j;
  switch (DetectLogFormat(a.input)) {
    case LogFormat::kULog: {
      ULogReadOptions options;
      options.strict = a.strict;
      Result<ULogContents> log = ReadULog(a.input, options);
      if (!log.ok()) return ReportError(kInspectName, log.error());
      j = InspectULog(*log);
      break;
    }
    case LogFormat::kDataFlash: {
      DataFlashReadOptions options;
      options.strict = a.strict;
      Result<DataFlashContents> log = ReadDataFlash(a.input, options);
      if (!log.ok()) return ReportError(kInspectName, log.error());
      j = InspectDataFlash(*log);
      break;
    }
    case LogFormat::kRosBag: {
      BagReadOptions options;
      options.strict = a.strict;
      Result<BagListing> bag = ListBag(a.input, options);
      if (!bag.ok()) return ReportError(kInspectName, bag.error());
      j = InspectBag(*bag);
      break;
    }
    default:
      return ReportError(kInspectName, InvalidInput(a.input + ": not a PX4 ULog, ArduPilot DataFlash log or ROS bag (by its "
                                                       "first bytes); inspect reads flight-controller logs and bags"));
  }
  j["input"] = a.input;
  if (!a.json_path.empty()) {
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kInspectName, s.error());
  }
  if (a.json_path != "-") {
    if (j.contains("gyro_instances")) PrintText(j); else PrintBag(j);
  }
  return kExitOk;
}

Command MakeInspect(CLI::App& app) {
  auto a = std::make_shared<InspectArgs>();
  CLI::App* sub = app.add_subcommand(kInspectName, "List what a PX4 ULog or ArduPilot DataFlash log, or a ROS bag, holds");
  sub->footer(
      "Prints the topics (ULog) or message types (DataFlash), every sensor instance (gyro, accel, baro)\n"
      "with rows, device id (ULog device_id; DataFlash INS_GYR*_ID / INS_ACC*_ID / BARO*_DEVID), mean\n"
      "sample rate and temperature range, the damage found (byte ranges skipped, rows lost), and the\n"
      "thermal-compensation parameters found\n"
      "(PX4 TC_G_ENABLE / TC_G{i}_ID, ArduPilot INS_TCAL{n}_ENABLE). Example: gyrocomp inspect -i log.ulg\n"
      "ROS bags (ROS 1, MCAP, rosbag2 .db3 or folder): every topic with type, encoding, messages and\n"
      "mean rate (receive times), and the damage found. Example: gyrocomp inspect -i imu.mcap");
  AddInputOption(sub, "-i,--input", &a->input, "Input log (ULog, DataFlash or ROS bag, recognised by its first bytes)")->required();
  AddOutputOption(sub, "--json", &a->json_path, "Write the listing as JSON ('-' = stdout, then no text)");
  sub->add_flag("--strict", a->strict,
                "Refuse a damaged ULog / DataFlash log, ROS 1 bag, MCAP or rosbag2 .db3 at its first bad record (exit 2, "
                "naming the byte offset or message id)");
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kInspectRegistrar(kInspectName, 22, &MakeInspect);

}  // namespace
}  // namespace gyrocomp::cli
