// gyrocomp inspect: what a PX4 ULog or ArduPilot DataFlash log holds (topics / messages, gyro
// instances with rows, sample rate and temperature range, compensation parameters found). The
// listing is the library's (gyrocomp/io/inspect.h, InspectLog); this file prints it.
#include <algorithm>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "gyrocomp/io/inspect.h"
#include "table_printer.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kInspectName = "inspect";

struct InspectArgs {
  std::string input;
  std::string json_path;
  bool strict = false;
};

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
  InspectOptions options;
  options.strict = a.strict;
  Result<LogInventory> inventory = InspectLog(a.input, options);
  if (!inventory.ok()) return ReportError(kInspectName, inventory.error());
  nlohmann::json j = std::move(inventory->listing);
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
