// gyrocomp convert: what the ULog / DataFlash reader sees, as a CSV (time_s, x_rad_s, y_rad_s,
// z_rad_s, temp_c), so users can check it and tests can compare it with reference extracts.
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "gyrocomp/io/bag_log.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/io/log_damage.h"

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
  bool strict = false;                 // a damaged ULog / DataFlash / bag record is an error
};

// A ROS bag's IMU topic: --topic, --time, --strict.
Result<FlightLogTable> ReadBag(const ConvertArgs& a) {
  LogSpec spec;
  spec.topic = a.topic;
  spec.bag_time = a.time_source == "receive" ? BagTimeSource::kReceive : BagTimeSource::kHeader;
  BagReadOptions options = BagOptionsFromSpec(spec);
  options.strict = a.strict;
  Result<BagImuTable> bag = ReadBagImu(a.input, options);
  if (!bag) return bag.error();
  return BagFlightLog(std::move(*bag));
}

int Run(const ConvertArgs& a) {
  const LogFormat format = DetectLogFormat(a.input);
  if (format == LogFormat::kCsv) {
    return ReportError(kConvertName, InvalidInput(a.input + ": not a PX4 ULog, ArduPilot DataFlash log or ROS bag (by its "
                                                     "first bytes); convert reads flight-controller logs and bags"));
  }
  Result<FlightLogTable> log = format == LogFormat::kRosBag ? ReadBag(a) : ReadFlightLog(a.input, a.instance, a.strict);
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
    j["damage"] = DamageJson(log->damage);
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kConvertName, s.error());
  }
  Note(kConvertName, log->origin + ": " + std::to_string(rows) + " rows -> " + a.output);
  return kExitOk;
}

Command MakeConvert(CLI::App& app) {
  auto a = std::make_shared<ConvertArgs>();
  CLI::App* sub = app.add_subcommand(kConvertName, "Write the gyro rows of a PX4 ULog or ArduPilot DataFlash log, or a ROS bag's IMU topic, as CSV");
  sub->footer(
      "Columns: time_s (log timestamps / 1e6), x_rad_s, y_rad_s, z_rad_s, temp_c (absent for ULog\n"
      "sensor_combined). ULog: sensor_gyro multi_id N (sensor_combined when there is no sensor_gyro),\n"
      "x/y/z as logged (PX4's sensor frame). DataFlash: IMU instance N (old logs: IMU, IMU2, IMU3),\n"
      "x/y/z rotated from ArduPilot's board frame back to the sensor frame (the rotation\n"
      "AHRS_ORIENTATION names is undone) and, with INS_TCALn_ENABLE = 1, the firmware's thermal\n"
      "correction added back (both said on stderr when done). No sampling checks: the rows are what\n"
      "the reader sees. A damaged ULog / DataFlash record is skipped to the next valid record (a\n"
      "warning gives the byte ranges and rows lost; --strict refuses instead).\n"
      "Example: gyrocomp convert -i log.ulg --instance 0 -o gyro0.csv\n"
      "ROS bags (ROS 1, MCAP, rosbag2 .db3 / folder): time_s (header stamp, or --time receive),\n"
      "x_rad_s, y_rad_s, z_rad_s (angular_velocity), x_m_s2, y_m_s2, z_m_s2 (linear_acceleration),\n"
      "temp_c (a sensor_msgs/Temperature topic joined by nearest time). A damaged ROS 1 bag or MCAP record\n"
      "or chunk, or a .db3 row SQLite cannot read, is skipped the same way (--strict refuses).\n"
      "gyrocomp convert -i imu.mcap --topic /imu0 -o imu.csv");
  AddInputOption(sub, "-i,--input", &a->input, "Input log (ULog, DataFlash or ROS bag, recognised by its first bytes)")->required();
  sub->add_option("--instance", a->instance, "Gyro instance (default: the only one; several are listed)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--topic", a->topic, "ROS bag: the sensor_msgs/Imu topic (default: the only one)");
  sub->add_option("--time", a->time_source, "ROS bag: row time from the header stamp (header) or receive time (receive)")
      ->check(CLI::IsMember({"header", "receive"}))
      ->capture_default_str();
  sub->add_flag("--strict", a->strict,
                "Refuse a damaged ULog / DataFlash log, ROS 1 bag, MCAP or rosbag2 .db3 at its first bad record (exit 2, "
                "naming the byte offset or message id)");
  AddOutputOption(sub, "-o,--output", &a->output, "Output CSV (.gz: gzip; '-' = stdout)")->required();
  AddOutputOption(sub, "--json", &a->json_path, "Write what was converted as JSON ('-' = stdout)");
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kConvertRegistrar(kConvertName, 24, &MakeConvert);

}  // namespace
}  // namespace gyrocomp::cli
