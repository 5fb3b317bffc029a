// gyrocomp.read_log: CSV, PX4 ULog or ArduPilot DataFlash (the flight-log readers) as a GyroLog;
// gyrocomp.read_log_rows: the rows the flight-log and bag readers see, unchecked (`gyrocomp convert`).
#include <nlohmann/json.hpp>

#include "bindings.h"

#include "gyrocomp/core/units.h"
#include "gyrocomp/io/bag.h"
#include "gyrocomp/io/bag_log.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/gyro_log.h"
#include "gyrocomp/io/log_damage.h"

namespace gyrocomp::python {

LogSpec ReadLogSpec(Kwargs& kw) {
  LogSpec s;
  kw.Get("time_col", &s.time_col);
  py::object rate_cols = kw.Take("rate_cols");
  if (!rate_cols.is_none()) {
    s.rate_cols = py::isinstance<py::str>(rate_cols) ? std::vector<std::string>{rate_cols.cast<std::string>()}
                                                     : rate_cols.cast<std::vector<std::string>>();
  }
  kw.GetParsed("rate_unit", &s.rate_unit, ParseRateUnit, "must be dps, rads or dph");
  kw.Get("temp_col", &s.temp_col);
  kw.Get("temp_required", &s.temp_required);
  kw.Get("rates_required", &s.rates_required);
  kw.Get("fs_hz", &s.fs_hz);
  kw.Get("resample_hz", &s.resample_hz);
  kw.Get("min_samples", &s.min_samples);
  kw.Get("jitter_tolerance", &s.jitter_tolerance);
  kw.Get("max_irregular_fraction", &s.max_irregular_fraction);
  kw.Get("gap_factor", &s.gap_factor);
  kw.Get("instance", &s.instance);
  return s;
}

namespace {

py::dict SamplingDict(const SamplingReport& r) {
  return py::dict(py::arg("fs_hz") = r.fs_hz, py::arg("median_dt_s") = r.median_dt_s, py::arg("min_dt_s") = r.min_dt_s,
                  py::arg("max_dt_s") = r.max_dt_s, py::arg("num_intervals") = r.num_intervals,
                  py::arg("num_irregular") = r.num_irregular, py::arg("num_gaps") = r.num_gaps,
                  py::arg("longest_gap_s") = r.longest_gap_s, py::arg("irregular") = r.irregular,
                  py::arg("resampled") = r.resampled, py::arg("rows_in") = r.rows_in, py::arg("rows_out") = r.rows_out,
                  py::arg("brief_report") = r.BriefReport());
}

}  // namespace

void BindIo(py::module_& m) {
  m.def(
      "read_log_rows",
      [](const std::string& path, std::optional<int> instance, std::optional<std::string> topic,
         const std::string& time_source, bool strict) {
        if (time_source != "header" && time_source != "receive")
          throw py::value_error("read_log_rows(): time_source=" + time_source + ": must be header or receive");
        // As `gyrocomp convert`: the format by the first bytes; a bag's IMU topic, or a flight log's
        // gyro instance (ReadFlightLog: DataFlash rotated to the sensor frame, TCAL added back).
        const LogFormat format = DetectLogFormat(path);
        if (format == LogFormat::kCsv)
          throw py::value_error(path + ": not a PX4 ULog, ArduPilot DataFlash log or ROS bag (by its first bytes); "
                                       "read_log_rows reads flight-controller logs and bags (read_log reads a CSV)");
        FlightLogTable t = Unwrap(WithoutGil([&]() -> Result<FlightLogTable> {
          if (format != LogFormat::kRosBag) return ReadFlightLog(path, instance, strict);
          LogSpec spec;
          spec.topic = topic;
          spec.bag_time = time_source == "receive" ? BagTimeSource::kReceive : BagTimeSource::kHeader;
          BagReadOptions options = BagOptionsFromSpec(spec);
          options.strict = strict;
          Result<BagImuTable> bag = ReadBagImu(path, options);
          if (!bag.ok()) return bag.error();
          return BagFlightLog(std::move(*bag));
        }));
        py::dict d;
        d["format"] = std::string(LogFormatName(t.format));
        d["origin"] = t.origin;
        d["instance"] = t.instance;
        d["device_id"] = t.device_id;
        d["rows"] = t.table.num_rows();
        d["names"] = t.table.names;
        py::dict columns;  // name -> numpy array, in file order (time_s, x_rad_s, ...)
        for (std::size_t j = 0; j < t.table.names.size(); ++j)
          columns[py::str(t.table.names[j])] = ToNumpy(std::move(t.table.columns[j]));
        d["columns"] = columns;
        d["warnings"] = t.warnings;
        d["damage"] = py::module_::import("json").attr("loads")(DamageJson(t.damage).dump());
        return d;
      },
      py::arg("path"), py::kw_only(), py::arg("instance") = py::none(), py::arg("topic") = py::none(),
      py::arg("time_source") = "header", py::arg("strict") = false,
      "The rows a PX4 ULog, ArduPilot DataFlash log or ROS bag IMU topic holds, without sampling checks (gyrocomp "
      "convert): columns {name: array} (time_s, x_rad_s, y_rad_s, z_rad_s, temp_c; a bag's x_m_s2, ...), origin, "
      "instance, device_id, warnings, damage.");

  m.def(
      "read_log",
      [](const std::string& path, const py::kwargs& kwargs) {
        const LogSpec spec = ReadAll(kwargs, "read_log", ReadLogSpec);
        GyroLog log = Unwrap(WithoutGil([&] { return ReadGyroLog(path, spec); }));
        py::dict d;
        d["source"] = log.source;
        d["fs_hz"] = log.fs_hz;
        d["time_s"] = ToNumpy(std::move(log.time_s));
        d["axis_names"] = log.axis_names;
        py::dict rates;  // axis name -> deg/s
        for (std::size_t a = 0; a < log.rate_dps.size(); ++a) rates[py::str(log.axis_names[a])] = ToNumpy(std::move(log.rate_dps[a]));
        d["rate_dps"] = rates;
        d["temp_c"] = log.temp_c.empty() ? py::object(py::none()) : py::object(ToNumpy(std::move(log.temp_c)));
        d["sampling"] = SamplingDict(log.sampling);
        d["device_id"] = log.device_id;
        d["origin"] = log.origin;
        d["warnings"] = log.warnings;
        return d;
      },
      py::arg("path"),
      "A gyro log (CSV, .csv.gz, PX4 ULog, ArduPilot DataFlash; LogSpec as keywords: time_col, rate_cols, "
      "rate_unit, temp_col, fs_hz, resample_hz, instance, ...). rate_dps: {axis name: array in deg/s}.");
}

}  // namespace gyrocomp::python
