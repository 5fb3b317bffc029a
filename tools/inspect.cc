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
#include "table_printer.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kInspectName = "inspect";

struct InspectArgs {
  std::string input;
  std::string json_path;
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
  nlohmann::json gyros = nlohmann::json::array();
  for (const DataFlashImuSeries& s : log.imus) gyros.push_back(InstanceJson(s.message, s.instance, s.time_us, s.temp_c, {}));
  j["gyro_instances"] = gyros;
  // ArduPilot thermal calibration: INS_TCAL{n}_ENABLE for IMU n-1.
  j["compensation_parameters"] = CompensationJson(log.parameters, "INS_TCAL");
  j["warnings"] = log.warnings;
  return j;
}

// A ROS bag (issue 25): every topic with its type, encoding, message count and mean rate (by
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
  return j;
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
  for (const auto& g : j["gyro_instances"]) {
    const auto& t = g["temp_range_c"];
    rows.push_back({g["source"].get<std::string>(), std::to_string(g["instance"].get<int>()),
                    std::to_string(g["rows"].get<std::size_t>()),
                    g["device_id"].is_null() ? "-" : std::to_string(g["device_id"].get<std::uint32_t>()),
                    FormatNumber(g["sample_rate_hz"].is_null() ? std::nullopt : std::optional<double>(g["sample_rate_hz"].get<double>())),
                    t.is_null() ? "none" : FormatNumber(t[0].get<double>()) + " .. " + FormatNumber(t[1].get<double>())});
  }
  std::cout << FormatTable({"gyro", "instance", "rows", "device_id", "rate_hz", "temp_c"}, rows);
  std::cout << "compensation parameters: " << (j["compensation_parameters"].empty() ? "none found" : j["compensation_parameters"].dump())
            << "\n";
  for (const auto& w : j["warnings"]) std::cout << "warning: " << w.get<std::string>() << "\n";
}

int Run(const InspectArgs& a) {
  nlohmann::json j;
  switch (DetectLogFormat(a.input)) {
    case LogFormat::kULog: {
      Result<ULogContents> log = ReadULog(a.input);
      if (!log.ok()) return ReportError(kInspectName, log.error());
      j = InspectULog(*log);
      break;
    }
    case LogFormat::kDataFlash: {
      Result<DataFlashContents> log = ReadDataFlash(a.input);
      if (!log.ok()) return ReportError(kInspectName, log.error());
      j = InspectDataFlash(*log);
      break;
    }
    case LogFormat::kRosBag: {
      Result<BagListing> bag = ListBag(a.input);
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
      "Prints the topics (ULog) or message types (DataFlash), the gyro instances with rows, device id,\n"
      "mean sample rate and temperature range, and the thermal-compensation parameters found\n"
      "(PX4 TC_G_ENABLE / TC_G{i}_ID, ArduPilot INS_TCAL{n}_ENABLE). Example: gyrocomp inspect -i log.ulg\n"
      "ROS bags (ROS 1, MCAP, rosbag2 .db3 or folder): every topic with type, encoding, messages and\n"
      "mean rate (receive times). Example: gyrocomp inspect -i imu.mcap");
  AddInputOption(sub, "-i,--input", &a->input, "Input log (ULog, DataFlash or ROS bag, recognised by its first bytes)")->required();
  AddOutputOption(sub, "--json", &a->json_path, "Write the listing as JSON ('-' = stdout, then no text)");
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kInspectRegistrar(kInspectName, 22, &MakeInspect);

}  // namespace
}  // namespace gyrocomp::cli
