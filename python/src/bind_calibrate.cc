// gyrocomp.calibrate: the calibrate stage (gyrocomp/calibrate/calibrate.h): every sensor of one
// board's flight logs, per-sensor results and the parameter file's text (docs/guides/python.md).
#include "bindings.h"

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
  return o;
}

py::dict CubicDict(const TemperatureCubic& c) {
  return py::dict(py::arg("ref_temp_c") = c.ref_temp_c, py::arg("temp_min_c") = c.temp_min_c,
                  py::arg("temp_max_c") = c.temp_max_c, py::arg("coeff") = std::vector<double>(c.coeff.begin(), c.coeff.end()));
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
  if (!s.calibrated()) return d;
  d["temp_min_c"] = s.temp_min_c;
  d["temp_max_c"] = s.temp_max_c;
  d["runs_combined"] = s.runs_combined;
  d["kind"] = DriftModelKindName(s.models[0].kind);
  py::list cubics;
  for (const TemperatureCubic& c : s.cubics) cubics.append(CubicDict(c));
  d["cubics"] = cubics;  // firmware unit, as in the parameter file
  d["static_weight"] = s.weights;
  d["projection_cost_rms"] = s.cost_rms;
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
        Kwargs kw(kwargs, "calibrate");
        const CalibrateOptions o = ReadCalibrateOptions(kw);
        kw.Done();
        CalibrateResult r = Unwrap(WithoutGil([&] { return CalibrateLogs(logs, o); }));
        py::dict d;
        d["inputs"] = r.inputs;
        py::list sensors;
        for (const CalibratedSensor& s : r.sensors) sensors.append(SensorDict(s));
        d["sensors"] = sensors;
        d["parameter_text"] = r.parameter_text;
        d["notes"] = r.notes;
        d["brief_report"] = r.BriefReport();
        return d;
      },
      py::arg("logs"),
      "Thermal calibration of every IMU sensor of one board's logs (PX4 ULog or ArduPilot DataFlash; the first "
      "is the primary run). CalibrateOptions as keywords: format ('px4' | 'ardupilot'), fit_rate_hz, min_span_c, "
      "min_rows, optimise_for, static_weight, validation_path, block_s. Returns the per-sensor results and "
      "parameter_text, the file `gyrocomp calibrate` writes.");
}

}  // namespace gyrocomp::python
