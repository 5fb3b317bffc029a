// Flight-controller logs as gyro tables (include/gyrocomp/io/flight_log.h).
#include "gyrocomp/io/flight_log.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <utility>

#include "gyrocomp/core/format.h"
#include "gyrocomp/io/bag_log.h"

namespace gyrocomp {

namespace {

// "0 (device_id 2424842, 6 rows), 1 (...)": the instances to choose from.
template <typename Series, typename Describe>
std::string ListInstances(const std::vector<Series>& all, Describe describe) {
  std::string s;
  for (const Series& g : all) s += (s.empty() ? "" : ", ") + describe(g);
  return s;
}

// The instance to take: the only one, or the one asked for; else an error listing them.
template <typename Series, typename InstanceOf, typename Describe>
Result<const Series*> PickInstance(const std::vector<Series>& all, std::optional<int> wanted, const std::string& source,
                                   const std::string& what, InstanceOf instance_of, Describe describe) {
  if (all.empty()) return InvalidInput(source + ": no " + what + " data in the log");
  if (!wanted) {
    if (all.size() == 1) return &all.front();
    return InvalidInput(source + ": " + std::to_string(all.size()) + " " + what + " instances: " +
                        ListInstances(all, describe) + "; choose one with --instance N");
  }
  for (const Series& g : all) {
    if (instance_of(g) == *wanted) return &g;
  }
  return InvalidInput(source + ": no " + what + " instance " + std::to_string(*wanted) + "; the log has " +
                      ListInstances(all, describe));
}

std::vector<double> Seconds(const std::vector<std::uint64_t>& us) {
  std::vector<double> t(us.size());
  for (std::size_t i = 0; i < us.size(); ++i) t[i] = static_cast<double>(us[i]) / 1e6;
  return t;
}

// A temperature that never changes (PX4 SITL logs 0.0) cannot carry a thermal model.
void WarnIfConstant(const std::vector<double>& temp_c, const std::string& source, const std::string& origin,
                    std::vector<std::string>* warnings) {
  if (temp_c.size() < 2) return;
  const auto [lo, hi] = std::minmax_element(temp_c.begin(), temp_c.end());
  if (*lo == *hi) {
    warnings->push_back(source + ": " + origin + ": the temperature is " + FormatNumber(*lo) +
                        " C in every row (a simulated sensor?); no thermal model can be fitted on it");
  }
}

// NaN / infinity in a logged value: refused, as ReadCsv refuses them in a CSV. "line" is the line
// of `gyrocomp convert`'s output (header = line 1), the row's timestamp says where in the log.
std::optional<Error> CheckFinite(const Table& table) {
  for (std::size_t j = 0; j < table.columns.size(); ++j) {
    const std::vector<double>& c = table.columns[j];
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (std::isfinite(c[i])) continue;
      return InvalidInput(table.source + ":" + std::to_string(i + 2) + ":" + std::to_string(j + 1) + ": " +
                          (std::isnan(c[i]) ? "NaN" : "infinity") + " in column '" + table.names[j] +
                          "' (row " + std::to_string(i) + ", time_s " + FormatNumber(table.columns[0][i]) + ")");
    }
  }
  return std::nullopt;
}

bool Enabled(const std::map<std::string, double>& params, const std::string& name, double* value) {
  const auto it = params.find(name);
  if (it == params.end()) return false;
  *value = it->second;
  return it->second != 0.0;
}

}  // namespace

std::string_view LogFormatName(LogFormat format) {
  switch (format) {
    case LogFormat::kULog: return "ulog";
    case LogFormat::kDataFlash: return "dataflash";
    case LogFormat::kRosBag: return "rosbag";
    default: return "csv";
  }
}

LogFormat DetectLogFormat(const std::string& path) {
  // Only regular files are peeked at: reading the first bytes of a pipe (stdin, `<(zcat x)`)
  // would take them away from the CSV reader.
  if (DetectBagFormat(path) != BagFormat::kNone) return LogFormat::kRosBag;  // issue 25 (files and bag folders)
  std::error_code ec;
  if (path == "-" || !std::filesystem::is_regular_file(path, ec)) return LogFormat::kCsv;
  std::ifstream in(path, std::ios::binary);
  std::uint8_t head[8] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  const auto n = static_cast<std::size_t>(in.gcount());
  if (HasULogMagic(head, n)) return LogFormat::kULog;
  if (HasDataFlashMagic(head, n)) return LogFormat::kDataFlash;
  return LogFormat::kCsv;
}

Result<FlightLogTable> FlightLogFromULog(const ULogContents& log, std::optional<int> instance) {
  FlightLogTable out;
  out.format = LogFormat::kULog;
  out.warnings = log.warnings;
  const bool combined = log.gyros.empty() && !log.combined.empty();
  const std::vector<ULogGyroSeries>& all = combined ? log.combined : log.gyros;
  const std::string what = combined ? "sensor_combined" : "sensor_gyro";
  if (log.gyros.empty() && log.combined.empty()) {
    return InvalidInput(log.source + ": no sensor_gyro or sensor_combined data in the log (" + log.BriefReport() + ")");
  }
  Result<const ULogGyroSeries*> pick = PickInstance(
      all, instance, log.source, what, [](const ULogGyroSeries& g) { return g.multi_id; },
      [](const ULogGyroSeries& g) {
        return std::to_string(g.multi_id) + " (" + std::to_string(g.timestamp_us.size()) + " rows" +
               (g.device_id ? ", device_id " + std::to_string(*g.device_id) : std::string()) + ")";
      });
  if (!pick) return pick.error();
  const ULogGyroSeries& g = **pick;
  out.instance = g.multi_id;
  out.device_id = g.device_id;
  out.origin = "ULog " + what + " multi_id " + std::to_string(g.multi_id);
  out.table.source = log.source + "[" + what + "." + std::to_string(g.multi_id) + "]";
  out.table.Add(kFlightTimeCol, Seconds(g.timestamp_us));
  out.table.Add(kFlightRateCols[0], g.x_rad_s);
  out.table.Add(kFlightRateCols[1], g.y_rad_s);
  out.table.Add(kFlightRateCols[2], g.z_rad_s);
  if (!g.temperature_c.empty()) {
    out.table.Add(kFlightTempCol, g.temperature_c);
    WarnIfConstant(g.temperature_c, log.source, out.origin, &out.warnings);
  } else {
    out.warnings.push_back(log.source + ": " + out.origin + " has no temperature" +
                           (combined ? " (the log has no sensor_gyro data, only sensor_combined, which logs none)" : ""));
  }
  if (auto e = CheckFinite(out.table)) return *e;
  double v = 0;
  if (Enabled(log.parameters, "TC_G_ENABLE", &v)) {
    out.warnings.push_back("WARNING: " + log.source + ": TC_G_ENABLE = " + FormatNumber(v) +
                           " in the log's parameters: PX4 was applying its gyro thermal compensation; " +
                           (combined ? "sensor_combined rates are compensated" :
                                       "depending on the PX4 version sensor_gyro rates may be compensated") +
                           ", and a model fitted on compensated rates learns the residual, not the sensor's drift");
  }
  return out;
}

Result<FlightLogTable> FlightLogFromDataFlash(const DataFlashContents& log, std::optional<int> instance) {
  FlightLogTable out;
  out.format = LogFormat::kDataFlash;
  out.warnings = log.warnings;
  Result<const DataFlashImuSeries*> pick = PickInstance(
      log.imus, instance, log.source, "IMU", [](const DataFlashImuSeries& s) { return s.instance; },
      [](const DataFlashImuSeries& s) {
        return std::to_string(s.instance) + " (" + s.message + ", " + std::to_string(s.time_us.size()) + " rows)";
      });
  if (!pick) return pick.error();
  const DataFlashImuSeries& s = **pick;
  out.instance = s.instance;
  out.origin = "DataFlash " + s.message + (s.message == "IMU" ? " I=" + std::to_string(s.instance) : std::string());
  out.table.source = log.source + "[IMU." + std::to_string(s.instance) + "]";
  out.table.Add(kFlightTimeCol, Seconds(s.time_us));
  out.table.Add(kFlightRateCols[0], s.gyr_x_rad_s);
  out.table.Add(kFlightRateCols[1], s.gyr_y_rad_s);
  out.table.Add(kFlightRateCols[2], s.gyr_z_rad_s);
  if (s.temp_c.size() == s.time_us.size()) {
    out.table.Add(kFlightTempCol, s.temp_c);
    WarnIfConstant(s.temp_c, log.source, out.origin, &out.warnings);
  } else {
    out.warnings.push_back(log.source + ": " + out.origin + " has no temperature field T");
  }
  if (auto e = CheckFinite(out.table)) return *e;
  out.warnings.push_back("WARNING: " + log.source + ": ArduPilot logs IMU rates after its gyro offset correction "
                         "and rotation to the board frame; they are not the sensor's raw output");
  double v = 0;
  const std::string tcal = "INS_TCAL" + std::to_string(s.instance + 1) + "_ENABLE";
  if (Enabled(log.parameters, tcal, &v)) {
    out.warnings.push_back("WARNING: " + log.source + ": " + tcal + " = " + FormatNumber(v) +
                           " in the log's parameters: the logged rates of this IMU are already thermally "
                           "compensated (1) or were being learned (2); a model fitted on them learns the residual");
  }
  return out;
}

Result<FlightLogTable> ReadFlightLog(const std::string& path, std::optional<int> instance) {
  switch (DetectLogFormat(path)) {
    case LogFormat::kULog: {
      Result<ULogContents> log = ReadULog(path);
      if (!log) return log.error();
      return FlightLogFromULog(*log, instance);
    }
    case LogFormat::kDataFlash: {
      Result<DataFlashContents> log = ReadDataFlash(path);
      if (!log) return log.error();
      return FlightLogFromDataFlash(*log, instance);
    }
    case LogFormat::kRosBag: {  // issue 25: the IMU topic of a ROS bag (gyrocomp/io/bag_log.h)
      Result<BagImuTable> bag = ReadBagImu(path, BagReadOptions{});
      if (!bag) return bag.error();
      return BagFlightLog(std::move(*bag));
    }
    default:
      return InvalidArgument(path + ": neither a ULog nor a DataFlash log (by its first bytes)");
  }
}

Result<LogTableRead> ReadLogTable(const std::string& path, const LogSpec& spec) {
  LogTableRead out;
  out.spec = spec;
  out.format = DetectLogFormat(path);
  if (out.format == LogFormat::kRosBag) return ReadBagLogTable(path, spec);  // issue 25
  if (out.format == LogFormat::kCsv) {
    CsvReadOptions read;
    read.max_memory_bytes = spec.max_memory_bytes;
    Result<Table> table = ReadCsv(path, read);
    if (!table) return table.error();
    out.table = std::move(*table);
    return out;
  }
  Result<FlightLogTable> flight = ReadFlightLog(path, spec.instance);
  if (!flight) return flight.error();
  if (spec.on_warning) {
    for (const std::string& w : flight->warnings) spec.on_warning(w);
  }
  out.table = std::move(flight->table);
  flight->table = Table{};
  out.spec.time_col = kFlightTimeCol;
  out.spec.temp_col = kFlightTempCol;
  if (spec.rate_cols == LogSpec{}.rate_cols) out.spec.rate_cols.assign(std::begin(kFlightRateCols), std::end(kFlightRateCols));
  out.spec.rate_unit = RateUnit::kRadPerSec;
  if (spec.temp_required && out.table.Find(kFlightTempCol) < 0) {
    return InvalidInput(path + ": " + flight->origin + " logs no gyro temperature, and this command needs one" +
                        (flight->origin.find("sensor_combined") != std::string::npos
                             ? " (log sensor_gyro in PX4 to get it)" : ""));
  }
  out.flight = std::move(*flight);
  return out;
}

void AttachFlightLogInfo(const LogTableRead& read, GyroLog* log) {
  if (!read.flight) return;
  log->device_id = read.flight->device_id;
  log->origin = read.flight->origin;
  log->warnings = read.flight->warnings;
}

}  // namespace gyrocomp
