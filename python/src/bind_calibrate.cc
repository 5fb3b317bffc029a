// gyrocomp.calibrate: the calibrate stage (gyrocomp/calibrate/calibrate.h): every sensor of one
// board's flight logs, per-sensor results and the parameter file's text (docs/guides/python.md).
#include "bindings.h"

#include <cmath>

#include "gyrocomp/calibrate/calibrate.h"

namespace gyrocomp::python {
namespace {

CalibrateOptions ReadCalibrateOptions(Kwargs& kw) {
  CalibrateOptions o;
  kw.Get("format", &o.format);
  kw.Get("fit_rate_hz", &o.fit_rate_hz);
  kw.Get("min_span_c", &o.min_span_c);
  kw.Get("min_rows", &o.min_rows);
  kw.Get("optimise_for", &o.optimise_for);
  kw.Get("static_weight", &o.static_weight);
  kw.Get("validation_path", &o.validation_path);
  kw.Get("block_s", &o.block_s);
  kw.Get("min_still_s", &o.min_still_s);
  kw.Get("still_rate_hz", &o.still_rate_hz);
  kw.Get("still_threshold", &o.still.threshold);
  return o;
}

py::dict CubicDict(const TemperatureCubic& c) {
  return py::dict(py::arg("ref_temp_c") = c.ref_temp_c, py::arg("temp_min_c") = c.temp_min_c,
                  py::arg("temp_max_c") = c.temp_max_c, py::arg("coeff") = std::vector<double>(c.coeff.begin(), c.coeff.end()));
}

py::array_t<std::int64_t> Indices(const std::vector<int>& v) {
  return ToNumpy(std::vector<std::int64_t>(v.begin(), v.end()));
}

// The rows the fit saw (what the calibrate report draws under the cubics): temp_c (rows), values
// (axes x rows, firmware unit), log (index into inputs) and group (the constant each row shares).
py::dict FitRowsDict(const CalibratedSensor::FitRows& r) {
  return py::dict(py::arg("time_s") = ToNumpy(std::vector<double>(r.time_s)),
                  py::arg("temp_c") = ToNumpy(std::vector<double>(r.temp_c)), py::arg("values") = ToNumpy2d(r.values),
                  py::arg("log") = Indices(r.log), py::arg("group") = Indices(r.group));
}

// Per axis, the exported cubic's band against temperature: level, z, temp_c, sd (firmware unit;
// empty: no band, band_reason says why).
py::list CurveBandsList(const std::vector<CalibratedSensor::CurveBand>& bands) {
  py::list l;
  for (const CalibratedSensor::CurveBand& b : bands)
    l.append(py::dict(py::arg("level") = b.level, py::arg("z") = b.z, py::arg("temp_c") = ToNumpy(std::vector<double>(b.temp_c)),
                      py::arg("sd") = ToNumpy(std::vector<double>(b.sd))));
  return l;
}

py::dict SensorDict(const CalibratedSensor& s) {
  py::dict d;
  d["type"] = s.type;
  d["instance"] = s.instance;
  d["device_id"] = s.device_id ? py::object(py::int_(*s.device_id)) : py::object(py::none());
  d["slot"] = s.slot;
  d["status"] = s.calibrated() ? "calibrated" : "skipped";
  d["reason"] = s.reason;
  d["unit"] = s.unit;
  d["cols"] = s.cols;
  d["fit"] = s.fit;
  const CalibratedSensor::Identification& id = s.identification;
  d["identification"] = py::dict(py::arg("statement") = id.statement, py::arg("would_help") = id.would_help,
                                 py::arg("temp_min_c") = id.temp_min_c, py::arg("temp_max_c") = id.temp_max_c,
                                 py::arg("identified_span_c") = id.identified_span_c, py::arg("overlap_c") = id.overlap_c,
                                 py::arg("logs") = id.logs, py::arg("logs_with_still") = id.logs_with_still,
                                 py::arg("still_s") = id.still_s);
  if (!s.calibrated()) return d;
  d["curve_sd"] = s.curve_sd;
  if (s.fit == "pooled") {  // as calibrate --json: the lag search and each axis's dT/dt gain
    auto finite = [](double v) { return std::isfinite(v) ? py::object(py::float_(v)) : py::object(py::none()); };
    d["temp_lag_s"] = s.temp_lag_s;
    d["lag_term"] = py::dict(py::arg("gain") = s.lag_term.pairs ? finite(s.lag_term.gain) : py::object(py::none()),
                             py::arg("gain_se") = s.lag_term.pairs ? finite(s.lag_term.se) : py::object(py::none()),
                             py::arg("groups") = s.lag_term.pairs, py::arg("admitted") = s.lag_term.Admitted());
    d["rate_gain"] = s.rate_gain;
    // The state --optimise-for warm-up / both take the kept term at (None: no term kept).
    d["heating_state"] = s.heating_state_kind.empty()
                             ? py::object(py::none())
                             : py::object(py::dict(py::arg("kind") = s.heating_state_kind, py::arg("t0_c") = s.heating_state.t0_c,
                                                   py::arg("bin_c") = s.heating_state.bin_c,
                                                   py::arg("state") = s.heating_state.state));
  }
  d["temp_min_c"] = s.temp_min_c;
  d["temp_max_c"] = s.temp_max_c;
  d["runs_combined"] = s.runs_combined;
  d["kind"] = DriftModelKindName(s.models[0].kind);
  py::list cubics;
  for (const TemperatureCubic& c : s.cubics) cubics.append(CubicDict(c));
  d["cubics"] = cubics;  // firmware unit, as in the parameter file
  d["static_weight"] = s.weights;
  d["projection_cost_rms"] = s.cost_rms;
  d["to_model"] = s.to_model;  // firmware unit -> model_unit
  d["model_unit"] = s.model_unit;
  d["fit_rows"] = FitRowsDict(s.fit_rows);
  d["curve_bands"] = CurveBandsList(s.curve_bands);
  d["band_reason"] = s.band_reason;
  d["expected_error"] = ExpectedErrorText(s, false) + "; " + ExpectedErrorText(s, true);
  if (s.validation) {
    const auto& v = *s.validation;
    d["validation"] = py::dict(py::arg("reason") = v.reason, py::arg("rows") = v.rows, py::arg("raw_rms") = v.raw,
                               py::arg("cubic_rms") = v.cubic, py::arg("full_model_rms") = v.full_model);
  }
  return d;
}

}  // namespace

void BindCalibrate(py::module_& m) {
  m.def(
      "calibrate",
      [](const std::vector<std::string>& logs, const py::kwargs& kwargs) {
        const CalibrateOptions o = ReadAll(kwargs, "calibrate", ReadCalibrateOptions);
        CalibrateResult r = Unwrap(WithoutGil([&] { return CalibrateLogs(logs, o); }));
        py::dict d;
        d["inputs"] = r.inputs;
        py::list sensors;
        for (const CalibratedSensor& s : r.sensors) sensors.append(SensorDict(s));
        d["sensors"] = sensors;
        d["parameter_text"] = r.parameter_text;
        d["notes"] = r.notes;
        py::list logs_still;
        for (const CalibrateResult::LogStill& l : r.logs) {
          py::list segments, rejected;
          for (const StillSegment& g : l.detection.segments)
            segments.append(py::dict(py::arg("start_s") = g.start_s, py::arg("length_s") = g.length_s,
                                     py::arg("temp_min_c") = g.temp_min_c, py::arg("temp_max_c") = g.temp_max_c));
          for (const RejectedPart& p : l.detection.rejected)
            rejected.append(py::dict(py::arg("start_s") = p.start_s, py::arg("length_s") = p.length_s, py::arg("reason") = p.reason));
          logs_still.append(py::dict(py::arg("path") = l.path, py::arg("still_s") = l.detection.still_s,
                                     py::arg("total_s") = l.detection.total_s, py::arg("still_segments") = segments,
                                     py::arg("rejected") = rejected));
        }
        d["logs"] = logs_still;
        d["brief_report"] = r.BriefReport();
        return d;
      },
      py::arg("logs"),
      "Thermal calibration of every IMU sensor of one board's logs (PX4 ULog or ArduPilot DataFlash; the first "
      "is the primary run). CalibrateOptions as keywords: format ('px4' | 'ardupilot'), fit_rate_hz, min_span_c, "
      "min_rows, optimise_for, static_weight, validation_path, block_s, min_still_s, still_rate_hz, still_threshold. "
      "Only the still rows of each log feed the fit (logs: per log the still segments and the parts rejected); "
      "several logs or flights give one pooled cubic. Returns the per-sensor results (fit, identification) and "
      "parameter_text, the file `gyrocomp calibrate` writes.");
}

}  // namespace gyrocomp::python
