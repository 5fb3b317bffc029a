// gyrocomp convert: what the ULog / DataFlash reader sees, as a CSV (time_s, x_rad_s, y_rad_s,
// z_rad_s, temp_c), so users can check it and tests can compare it with reference extracts.
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "gyrocomp/io/bag_log.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/io.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kConvertName = "convert";

struct ConvertArgs {
  std::string input;
  std::optional<int> instance;
  std::string output;
  std::string json_path;
  std::optional<std::string> topic;   // ROS bag: the sensor_msgs/Imu topic
  std::string time_source = "header";  // ROS bag: header | receive
};

// A ROS bag's IMU topic (issue 25): --topic, --time.
Result<FlightLogTable> ReadBag(const ConvertArgs& a) {
  LogSpec spec;
  spec.topic = a.topic;
  spec.bag_time = a.time_source == "receive" ? BagTimeSource::kReceive : BagTimeSource::kHeader;
  Result<BagImuTable> bag = ReadBagImu(a.input, BagOptionsFromSpec(spec));
  if (!bag) return bag.error();
  return BagFlightLog(std::move(*bag));
}

int Run(const ConvertArgs& a) {
  const LogFormat format = DetectLogFormat(a.input);
  if (format == LogFormat::kCsv) {
    return ReportError(kConvertName, InvalidInput(a.input + ": not a PX4 ULog, ArduPilot DataFlash log or ROS bag (by its "
                                                     "first bytes); convert reads flight-controller logs and bags"));
  }
  Result<FlightLogTable> log = format == LogFormat::kRosBag ? ReadBag(a) : ReadFlightLog(a.input, a.instance);
  if (!log.ok()) return ReportError(kConvertName, log.error());
  for (const std::string& w : log->warnings) Note(kConvertName, w);
  const std::size_t rows = log->table.num_rows();
  if (Status s = WriteCsv(a.output, log->table); !s.ok()) return ReportError(kConvertName, s.error());
  if (!a.json_path.empty()) {
    nlohmann::json j;
    j["input"] = a.input;
    j["format"] = std::string(LogFormatName(log->format));
    j["origin"] = log->origin;
    j["instance"] = log->instance;
    j["device_id"] = log->device_id ? nlohmann::json(*log->device_id) : nlohmann::json();
    j["rows"] = rows;
    j["columns"] = log->table.names;
    j["output"] = a.output;
    j["warnings"] = log->warnings;
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kConvertName, s.error());
  }
  Note(kConvertName, log->origin + ": " + std::to_string(rows) + " rows -> " + a.output);
  return kExitOk;
}

Command MakeConvert(CLI::App& app) {
  auto a = std::make_shared<ConvertArgs>();
  CLI::App* sub = app.add_subcommand(kConvertName, "Write the gyro rows of a PX4 ULog or ArduPilot DataFlash log, or a ROS bag's IMU topic, as CSV");
  sub->footer(
      "Columns: time_s (log timestamps / 1e6), x_rad_s, y_rad_s, z_rad_s (as logged), temp_c (absent\n"
      "for ULog sensor_combined). ULog: sensor_gyro multi_id N (sensor_combined when there is no\n"
      "sensor_gyro); DataFlash: IMU instance N (old logs: IMU, IMU2, IMU3). No sampling checks: the\n"
      "rows are what the reader sees. Example: gyrocomp convert -i log.ulg --instance 0 -o gyro0.csv\n"
      "ROS bags (ROS 1, MCAP, rosbag2 .db3 / folder): time_s (header stamp, or --time receive),\n"
      "x_rad_s, y_rad_s, z_rad_s (angular_velocity), x_m_s2, y_m_s2, z_m_s2 (linear_acceleration),\n"
      "temp_c (a sensor_msgs/Temperature topic joined by nearest time). gyrocomp convert -i imu.mcap --topic /imu0 -o imu.csv");
  AddInputOption(sub, "-i,--input", &a->input, "Input log (ULog, DataFlash or ROS bag, recognised by its first bytes)")->required();
  sub->add_option("--instance", a->instance, "Gyro instance (default: the only one; several are listed)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--topic", a->topic, "ROS bag: the sensor_msgs/Imu topic (default: the only one)");
  sub->add_option("--time", a->time_source, "ROS bag: row time from the header stamp (header) or receive time (receive)")
      ->check(CLI::IsMember({"header", "receive"}))
      ->capture_default_str();
  AddOutputOption(sub, "-o,--output", &a->output, "Output CSV (.gz: gzip; '-' = stdout)")->required();
  AddOutputOption(sub, "--json", &a->json_path, "Write what was converted as JSON ('-' = stdout)");
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kConvertRegistrar(kConvertName, 24, &MakeConvert);

}  // namespace
}  // namespace gyrocomp::cli
