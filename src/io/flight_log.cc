// Flight-controller logs as gyro tables (include/gyrocomp/io/flight_log.h).
#include "gyrocomp/io/flight_log.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <utility>

#include "gyrocomp/core/format.h"
#include "gyrocomp/io/bag_log.h"
#include "gyrocomp/io/board_rotation.h"

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
  if (DetectBagFormat(path) != BagFormat::kNone) return LogFormat::kRosBag;  // files and bag folders
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

namespace {

// FlightLogFromULog; with `may_move` (ReadFlightLog's own contents, about to be dropped) the
// picked series' columns move into the table instead of being copied (memory).
Result<FlightLogTable> FromULog(const ULogContents& log, std::optional<int> instance, bool may_move) {
  const auto column = [may_move](const std::vector<double>& v) {
    return may_move ? std::move(const_cast<std::vector<double>&>(v)) : std::vector<double>(v);
  };
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
  out.table.Add(kFlightRateCols[0], column(g.x_rad_s));
  out.table.Add(kFlightRateCols[1], column(g.y_rad_s));
  out.table.Add(kFlightRateCols[2], column(g.z_rad_s));
  if (!g.temperature_c.empty()) {
    out.table.Add(kFlightTempCol, column(g.temperature_c));
    WarnIfConstant(out.table.columns.back(), log.source, out.origin, &out.warnings);
  } else {
    out.warnings.push_back(log.source + ": " + out.origin + " has no temperature" +
                           (combined ? " (the log has no sensor_gyro data, only sensor_combined, which logs none)" : ""));
  }
  if (auto e = CheckFinite(out.table)) return *e;
  // PX4 applies TC_G* in the sensors module (calibration::Gyroscope::Correct, in VehicleIMU),
  // after sensor_gyro is published by the driver: sensor_gyro rates are raw whatever TC_G_ENABLE
  // says. sensor_combined is published from the corrected data, so it is compensated.
  double v = 0;
  if (combined && Enabled(log.parameters, "TC_G_ENABLE", &v)) {
    out.warnings.push_back("WARNING: " + log.source + ": TC_G_ENABLE = " + FormatNumber(v) +
                           " in the log's parameters and the log has only sensor_combined, whose rates PX4 has "
                           "already thermally compensated: a model fitted on them learns the residual, not the "
                           "sensor's drift (log sensor_gyro for a calibration)");
  }
  return out;
}

}  // namespace

Result<FlightLogTable> FlightLogFromULog(const ULogContents& log, std::optional<int> instance) {
  return FromULog(log, instance, false);
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
  Result<DataFlashImuSeries> sensor = DataFlashImuToSensorFrame(log, **pick, &out.warnings);
  if (!sensor) return sensor.error();
  const DataFlashImuSeries& s = *sensor;
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
  return out;
}

namespace {

double Param(const std::map<std::string, double>& params, const std::string& name, double fallback) {
  const auto it = params.find(name);
  return it == params.end() ? fallback : it->second;
}

// ArduPilot's thermal correction of one sensor (AP_InertialSensor_tempcal.cpp, read at commit
// b4447821): polynomial_eval(tdiff, c) = (c1 + (c2 + c3 tdiff) tdiff) tdiff * 1e-6 (INV_SCALE_FACTOR),
// and correct_sensor: T and cal_temp clamped to [TMIN, TMAX], v -= p(T - 35), v += p(cal_temp - 35).
struct TcalSensor {
  double tmin_c = 0.0, tmax_c = 70.0;  // the firmware's defaults (var_info: TMIN 0, TMAX 70)
  double cal_temp_c = -300.0;          // INS_GYRn_CALTEMP / INS_ACCn_CALTEMP (-300: never calibrated)
  std::array<std::array<double, 3>, 3> coeff{};  // [order 1..3][axis x, y, z], scaled by 1e6
  double Poly(int axis, double temp_c) const {
    const double x = std::clamp(temp_c, tmin_c, tmax_c) - 35.0;  // TEMP_REFERENCE
    return (coeff[0][axis] + (coeff[1][axis] + coeff[2][axis] * x) * x) * x * 1.0e-6;
  }
  // What correct_sensor subtracted from the sensor at temp_c: p(T - 35) - p(Tcal - 35).
  double Correction(int axis, double temp_c) const { return Poly(axis, temp_c) - Poly(axis, cal_temp_c); }
};

TcalSensor ReadTcal(const std::map<std::string, double>& params, int imu, const char* kind) {
  static constexpr const char* kAxis[3] = {"X", "Y", "Z"};
  const std::string p = "INS_TCAL" + std::to_string(imu) + "_";
  TcalSensor t;
  t.tmin_c = Param(params, p + "TMIN", 0.0);
  t.tmax_c = Param(params, p + "TMAX", 70.0);
  // INS_GYR1_CALTEMP / INS_ACC1_CALTEMP (tempcal_IMU.py's "^INS_GYR(\d)_CALTEMP").
  t.cal_temp_c = Param(params, std::string("INS_") + kind + std::to_string(imu) + "_CALTEMP", -300.0);
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) t.coeff[k][a] = Param(params, p + kind + std::to_string(k + 1) + "_" + kAxis[a], 0.0);
  return t;
}

}  // namespace

namespace {
Result<DataFlashImuSeries> ToSensorFrame(const DataFlashContents& log, const DataFlashImuSeries& imu,
                                         std::vector<std::string>* notes);
}  // namespace

Result<DataFlashImuSeries> DataFlashImuToSensorFrame(const DataFlashContents& log, const DataFlashImuSeries& imu,
                                                     std::vector<std::string>* notes) {
  // A frame / compensation parameter of this IMU that changes while IMU rows are logged: the rows
  // after the first change are dropped and the values before it are used, as tempcal_IMU.py stops
  // capturing an IMU when its INS_TCAL enable changes (a learning run ends with 2 -> 1).
  const std::string n_str = std::to_string(imu.instance + 1);
  std::map<std::string, double> params = log.parameters;
  std::optional<DataFlashContents::ParameterChange> first;
  std::string first_name;
  for (const auto& [name, change] : log.parameters_changed_during_imu) {
    const bool mine = name == "AHRS_ORIENTATION" || name.rfind("INS_TCAL" + n_str + "_", 0) == 0 ||
                      name == "INS_GYR" + n_str + "_CALTEMP" || name == "INS_ACC" + n_str + "_CALTEMP";
    if (!mine) continue;
    if (change.time_us == 0)
      return InvalidInput(log.source + ": byte " + std::to_string(change.offset) + ": " + name +
                          " changes while IMU rows are logged and its PARM record has no TimeUS to cut the rows at");
    params[name] = change.before;
    if (!first || change.time_us < first->time_us) first = change, first_name = name;
  }
  DataFlashContents before_change;
  const DataFlashContents* plog = &log;
  DataFlashImuSeries kept;
  const DataFlashImuSeries* pimu = &imu;
  if (first) {
    std::size_t keep = 0;
    while (keep < imu.time_us.size() && imu.time_us[keep] < first->time_us) ++keep;
    kept = imu;
    for (auto* v : {&kept.gyr_x_rad_s, &kept.gyr_y_rad_s, &kept.gyr_z_rad_s, &kept.acc_x_m_s2, &kept.acc_y_m_s2,
                    &kept.acc_z_m_s2, &kept.temp_c})
      if (v->size() > keep) v->resize(keep);
    kept.time_us.resize(keep);
    before_change.source = log.source;
    before_change.parameters = std::move(params);
    plog = &before_change;
    pimu = &kept;
    notes->push_back(log.source + ": byte " + std::to_string(first->offset) + ": " + first_name + " changes from " +
                     FormatNumber(first->before) + " to " + FormatNumber(first->after) + " at TimeUS " +
                     std::to_string(first->time_us) + ": IMU " + std::to_string(imu.instance) + " rows kept up to it (" +
                     std::to_string(keep) + " of " + std::to_string(imu.time_us.size()) + "), under the values before");
  }
  return ToSensorFrame(*plog, *pimu, notes);
}

namespace {

Result<DataFlashImuSeries> ToSensorFrame(const DataFlashContents& log, const DataFlashImuSeries& imu,
                                         std::vector<std::string>* notes) {
  DataFlashImuSeries s = imu;
  const std::size_t n = s.time_us.size();
  const bool has_acc = s.acc_x_m_s2.size() == n && n > 0;
  // 1. Board rotation: AP_InertialSensor_Backend::_rotate_and_correct_gyro / _accel end with
  //    rotate(_board_orientation) (AHRS_ORIENTATION); undone with R^T as tempcal_IMU.py does.
  const double orientation = Param(log.parameters, "AHRS_ORIENTATION", 0.0);
  if (orientation != 0.0) {
    const auto r = orientation == std::floor(orientation) ? ArduPilotRotationMatrix(static_cast<int>(orientation))
                                                          : std::nullopt;
    if (!r) {
      return InvalidInput(log.source + ": AHRS_ORIENTATION = " + FormatNumber(orientation) +
                          " in the log's parameters: not one of ArduPilot's fixed rotations 0.." +
                          std::to_string(kArduPilotRotationCount - 1) +
                          " (100-102 are custom rotations set by CUST_ROT parameters, which gyrocomp does not read); "
                          "the rates cannot be brought back to the sensor frame");
    }
    for (std::size_t i = 0; i < n; ++i) {
      const auto g = RotateVectorInverse(*r, {s.gyr_x_rad_s[i], s.gyr_y_rad_s[i], s.gyr_z_rad_s[i]});
      s.gyr_x_rad_s[i] = g[0], s.gyr_y_rad_s[i] = g[1], s.gyr_z_rad_s[i] = g[2];
      if (!has_acc) continue;
      const auto a = RotateVectorInverse(*r, {s.acc_x_m_s2[i], s.acc_y_m_s2[i], s.acc_z_m_s2[i]});
      s.acc_x_m_s2[i] = a[0], s.acc_y_m_s2[i] = a[1], s.acc_z_m_s2[i] = a[2];
    }
    notes->push_back(log.source + ": AHRS_ORIENTATION = " + FormatNumber(orientation) + " (" +
                     *ArduPilotRotationName(static_cast<int>(orientation)) +
                     "): IMU rows rotated back from the board frame to the sensor frame");
  }
  // 2. Thermal correction already applied (INS_TCALn_ENABLE = 1; 2 = learning, rates raw).
  const int tcal_imu = s.instance + 1;
  const std::string enable_name = "INS_TCAL" + std::to_string(tcal_imu) + "_ENABLE";
  const double enable = Param(log.parameters, enable_name, 0.0);
  if (enable == 1.0 && s.temp_c.size() != n) {
    return InvalidInput(log.source + ": " + enable_name + " = 1 but IMU " + std::to_string(s.instance) +
                        " logs no temperature T: the thermal correction ArduPilot applied cannot be undone");
  }
  if (enable == 1.0) {
    const TcalSensor gyr = ReadTcal(log.parameters, tcal_imu, "GYR");
    const TcalSensor acc = ReadTcal(log.parameters, tcal_imu, "ACC");
    // The accel correction comes before INS_ACCnSCAL (_rotate_and_correct_accel): undo the scale.
    const std::string scal = tcal_imu == 1 ? "INS_ACCSCAL_" : "INS_ACC" + std::to_string(tcal_imu) + "SCAL_";
    const std::array<double, 3> scale = {Param(log.parameters, scal + "X", 1.0), Param(log.parameters, scal + "Y", 1.0),
                                         Param(log.parameters, scal + "Z", 1.0)};
    std::array<std::vector<double>*, 3> g = {&s.gyr_x_rad_s, &s.gyr_y_rad_s, &s.gyr_z_rad_s};
    std::array<std::vector<double>*, 3> a = {&s.acc_x_m_s2, &s.acc_y_m_s2, &s.acc_z_m_s2};
    for (std::size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) {
        (*g[k])[i] += gyr.Correction(k, s.temp_c[i]);
        if (has_acc && scale[k] != 0.0) (*a[k])[i] = (*a[k])[i] / scale[k] + acc.Correction(k, s.temp_c[i]);
      }
    notes->push_back(log.source + ": " + enable_name + " = 1 in the log's parameters: ArduPilot's thermal correction "
                     "(the log's INS_TCAL" + std::to_string(tcal_imu) + "_* coefficients, cal temperature " +
                     FormatNumber(gyr.cal_temp_c) + " C) added back to IMU " + std::to_string(s.instance) +
                     ": the rows are the sensor's own curve again (plus the constant boot offsets)");
  } else if (enable != 0.0 && enable != 2.0) {
    return InvalidInput(log.source + ": " + enable_name + " = " + FormatNumber(enable) +
                        " in the log's parameters: ArduPilot defines 0 (off), 1 (on), 2 (learning); cannot tell "
                        "whether the rows are compensated");
  }
  return s;
}

}  // namespace

Result<FlightLogTable> ReadFlightLog(const std::string& path, std::optional<int> instance, bool strict) {
  switch (DetectLogFormat(path)) {
    case LogFormat::kULog: {
      // Only the gyro rows (and, with an instance named, only its values) are kept, and they
      // move into the table: one gyro of a 1 GB log in well under 300 MB.
      ULogReadOptions options;
      options.keep_accel_baro = false;
      options.gyro_instance = instance;
      options.strict = strict;
      Result<ULogContents> log = ReadULog(path, options);
      if (!log) return log.error();
      std::vector<LogDamage> damage = std::move(log->damage);
      Result<FlightLogTable> t = FromULog(*log, instance, true);
      if (t) t->damage = std::move(damage);
      return t;
    }
    case LogFormat::kDataFlash: {
      DataFlashReadOptions options;  // only the chosen IMU's values (memory)
      options.imu_instance = instance;
      options.strict = strict;
      Result<DataFlashContents> log = ReadDataFlash(path, options);
      if (!log) return log.error();
      Result<FlightLogTable> t = FlightLogFromDataFlash(*log, instance);
      if (t) t->damage = log->damage;
      return t;
    }
    case LogFormat::kRosBag: {  // the IMU topic of a ROS bag (gyrocomp/io/bag_log.h)
      BagReadOptions options;
      options.strict = strict;
      Result<BagImuTable> bag = ReadBagImu(path, options);
      if (!bag) return bag.error();
      return BagFlightLog(std::move(*bag));
    }
    default:
      return InvalidArgument(path + ": neither a ULog nor a DataFlash log (by its first bytes)");
  }
}

Result<LogTableRead> ReadLogTable(const std::string& path, const LogSpec& spec, bool strict) {
  LogTableRead out;
  out.spec = spec;
  out.format = DetectLogFormat(path);
  if (out.format == LogFormat::kRosBag) return ReadBagLogTable(path, spec, strict);
  if (out.format == LogFormat::kCsv) {
    CsvReadOptions read;
    read.max_memory_bytes = spec.max_memory_bytes;
    if (spec.keep_cols) {  // only the columns the caller uses (memory)
      read.columns = *spec.keep_cols;
      read.columns->push_back(spec.time_col);
      read.columns->insert(read.columns->end(), spec.rate_cols.begin(), spec.rate_cols.end());
      read.columns->push_back(spec.temp_col);
    }
    Result<Table> table = ReadCsv(path, read);
    if (!table) return table.error();
    out.table = std::move(*table);
    return out;
  }
  Result<FlightLogTable> flight = ReadFlightLog(path, spec.instance, strict);
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
  log->instance = read.flight->instance;
  log->warnings = read.flight->warnings;
}

}  // namespace gyrocomp
