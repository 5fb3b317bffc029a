// gyrocomp.project_onto_cubic, px4_thermal_params, ardupilot_thermal_params (the export
// stage, include/gyrocomp/export/). The three-axis convenience export_params is Python
// (python/gyrocomp/__init__.py).
#include "bindings.h"

#include "gyrocomp/core/units.h"
#include "gyrocomp/export/axis_cubics.h"
#include "gyrocomp/export/c_export.h"
#include "gyrocomp/export/param_export.h"
#include "gyrocomp/export/thermal_cubic.h"

namespace gyrocomp::python {
namespace {

py::dict CubicDict(const TemperatureCubic& c) {
  return py::dict(py::arg("ref_temp_c") = c.ref_temp_c, py::arg("temp_min_c") = c.temp_min_c,
                  py::arg("temp_max_c") = c.temp_max_c, py::arg("coeff_dps") = c.coeff);
}

// Three cubics in deg/s (dicts as project_onto_cubic returns them) -> rad/s.
ThreeAxisCubics CubicsRadps(const py::sequence& cubics_dps) {
  if (py::len(cubics_dps) != 3) throw py::value_error("three axis cubics (x, y, z) are needed, got " + std::to_string(py::len(cubics_dps)));
  ThreeAxisCubics out;
  for (int k = 0; k < 3; ++k) {
    py::object c = cubics_dps[k];
    if (py::hasattr(c, "to_dict")) c = c.attr("to_dict")();
    const py::dict d = c.cast<py::dict>();
    TemperatureCubic t;
    t.ref_temp_c = d["ref_temp_c"].cast<double>();
    t.temp_min_c = d["temp_min_c"].cast<double>();
    t.temp_max_c = d["temp_max_c"].cast<double>();
    t.coeff = d["coeff_dps"].cast<std::array<double, 4>>();
    out[k] = t.Scaled(1.0 / units::kDegPerRad);  // deg/s -> rad/s, the autopilots' unit
  }
  return out;
}

// A run of export_cubics (calibration= / validation=): one path, read as `gyrocomp export -i` reads it.
std::optional<GyroLog> ReadExportRun(const py::object& path, const LogSpec& spec, const char* name) {
  if (path.is_none()) return std::nullopt;
  if (!py::isinstance<py::str>(path) && !py::hasattr(path, "__fspath__"))
    throw py::value_error(std::string("export_cubics(): ") + name + ": one run (a path), as `gyrocomp export -i` "
                          "takes one; several logs are pooled by calibrate");
  const std::string p = py::str(path);
  return Unwrap(WithoutGil([&] { return ReadGyroLog(p, spec); }));
}

py::dict ConditionDict(const CubicConditionError& e) {
  return py::dict(py::arg("total_rms_dps") = e.total_rms, py::arg("projection_rms_dps") = e.projection_rms,
                  py::arg("band_sd_rms_dps") = e.band_sd_rms, py::arg("samples") = e.num_samples);
}

py::object CostDict(const std::optional<CubicProjectionCost>& c) {
  if (!c) return py::none();
  return py::dict(py::arg("n_samples") = c->num_samples, py::arg("rms_dps") = c->rms, py::arg("max_abs_dps") = c->max_abs,
                  py::arg("model_span_dps") = c->model_span);
}

py::object WeightChoiceDict(const std::optional<StaticWeightChoice>& ch) {
  if (!ch) return py::none();
  auto e = [](const StaticEstimatorError& x) {
    return py::dict(py::arg("total_rms_dps") = x.total_rms, py::arg("rate_gain_rms_dps") = x.rate_gain_rms,
                    py::arg("noise_rms_dps") = x.noise_rms);
  };
  return py::dict(py::arg("chosen") = StaticWeightName(ch->chosen), py::arg("time") = e(ch->time),
                  py::arg("temperature") = e(ch->temperature), py::arg("unidentified_rate_gain_rms") = ch->rate_gain_rms,
                  py::arg("reason") = ch->reason);
}

// One axis of export_cubics: the keys of `gyrocomp export --json`'s axes, in deg/s.
py::dict AxisCubicDict(const AxisCubic& c) {
  py::dict d;
  d["cubic_dps"] = CubicDict(c.cubic_dps);
  d["static_weight"] = c.weight;
  d["weight_choice"] = WeightChoiceDict(c.weight_choice);
  d["weight_reason"] = c.weight_reason;
  d["cost_calibration"] = CostDict(c.calibration);
  d["cost_validation"] = CostDict(c.validation);
  if (c.expected) {
    d["expected_error"] = py::dict(
        py::arg("band_level") = c.expected->level, py::arg("steady") = ConditionDict(c.expected->steady),
        py::arg("warm_up") = c.expected->warm_up ? py::object(ConditionDict(*c.expected->warm_up)) : py::object(py::none()));
  } else {
    d["expected_error"] = py::none();
  }
  d["expected_reason"] = c.expected_reason;
  return d;
}

py::list ExportCubicsCall(const std::vector<DriftModel>& models, const py::object& calibration,
                          const py::object& validation, const std::string& static_weight, const py::kwargs& kwargs) {
  LogSpec spec = ReadAll(kwargs, "export_cubics", ReadLogSpec);
  spec.temp_required = true;
  AxisCubicsOptions o;
  const std::optional<StaticWeight> w = ParseStaticWeight(static_weight);
  if (!w) throw py::value_error("export_cubics(): static_weight=" + static_weight + ": must be auto, temperature or time");
  o.static_weight = *w;
  const std::optional<GyroLog> cal = ReadExportRun(calibration, spec, "calibration");
  const std::optional<GyroLog> val = ReadExportRun(validation, spec, "validation");
  std::vector<AxisDriftModel> axes;
  for (const DriftModel& model : models) axes.push_back({model.rate_col, model});
  const std::vector<AxisCubic> r = Unwrap(WithoutGil(
      [&] { return ExportAxisCubics(axes, cal ? &*cal : nullptr, val ? &*val : nullptr, o); }));
  py::list out;
  for (const AxisCubic& c : r) out.append(AxisCubicDict(c));
  return out;
}

CExportOptions ReadCExportOptions(Kwargs& kw) {
  CExportOptions o;
  kw.Get("prefix", &o.prefix);
  kw.Get("output_scale", &o.output_scale);
  kw.Get("output_unit", &o.output_unit);
  kw.Get("comments", &o.comments);
  return o;
}

py::dict GenerateCCall(const std::vector<DriftModel>& models, std::vector<std::string> axes, const py::kwargs& kwargs) {
  const CExportOptions o = ReadAll(kwargs, "generate_c", ReadCExportOptions);
  if (!axes.empty() && axes.size() != models.size())
    throw py::value_error("generate_c(): " + std::to_string(axes.size()) + " axis names for " +
                          std::to_string(models.size()) + " models");
  std::vector<AxisDriftModel> in;
  for (std::size_t k = 0; k < models.size(); ++k)
    in.push_back({axes.empty() ? models[k].summary.target_name : axes[k], models[k]});
  const GeneratedC g = Unwrap(GenerateCEvaluator(in, o));
  return py::dict(py::arg("header_name") = g.header_name, py::arg("header") = g.header,
                  py::arg("source_name") = g.source_name, py::arg("source") = g.source);
}

CubicProjectionOptions ReadProjectionOptions(Kwargs& kw) {
  CubicProjectionOptions o;
  kw.Get("grid_points", &o.grid_points);
  kw.Get("temp_min_c", &o.temp_min_c);
  kw.Get("temp_max_c", &o.temp_max_c);
  kw.Get("ref_temp_c", &o.ref_temp_c);
  return o;
}

py::dict ProjectOntoCubicCall(const DriftModel& model, const py::kwargs& kwargs) {
  const CubicProjectionOptions o = ReadAll(kwargs, "project_onto_cubic", ReadProjectionOptions);
  return CubicDict(Unwrap(WithoutGil([&] { return ProjectOntoCubic(model, o); })));
}

}  // namespace

void BindExport(py::module_& m) {
  m.def("export_cubics", &ExportCubicsCall, py::arg("models"), py::kw_only(), py::arg("calibration") = py::none(),
        py::arg("validation") = py::none(), py::arg("static_weight") = "auto",
        "The cubic each axis model exports to PX4 / ArduPilot (gyrocomp export --format px4|ardupilot): projected "
        "onto the range the models share, or the calibration run's static curve (static_weight: auto | "
        "temperature | time); costs on calibration / validation (one path each, read with read_log's "
        "keywords: rate_cols, temp_col, ...). One dict per axis: cubic_dps, static_weight, weight_choice, "
        "weight_reason, cost_calibration, cost_validation, expected_error.");
  m.def("generate_c", &GenerateCCall, py::arg("models"), py::arg("axes") = std::vector<std::string>{},
        "The dependency-free C99 evaluator of drift models (one per axis), as `gyrocomp export --format c`: "
        "a dict with header_name, header, source_name, source. Keywords (CExportOptions): prefix, output_scale, "
        "output_unit, comments; axes defaults to each model's target name.");
  m.def("project_onto_cubic", &ProjectOntoCubicCall, py::arg("model"),
        "Least-squares cubic in T (deg/s) of a drift model (CubicProjectionOptions as keywords).");
  m.def(
      "px4_thermal_params",
      [](const py::sequence& cubics_dps, std::optional<std::uint32_t> device_id, int index,
         const std::vector<std::string>& comments) {
        Px4ThermalParamOptions o;
        o.device_id = device_id;
        o.index = index;
        return Unwrap(WritePx4ThermalParams(CubicsRadps(cubics_dps), o, comments));
      },
      py::arg("cubics_dps"), py::kw_only(), py::arg("device_id") = py::none(), py::arg("index") = 0,
      py::arg("comments") = std::vector<std::string>{},
      "PX4 TC_G<index>_* parameter file text from three axis cubics in deg/s (docs/explanation/flight-controller-export.md).");

  m.def(
      "ardupilot_thermal_params",
      [](const py::sequence& cubics_dps, int imu, const std::vector<std::string>& comments) {
        ArduPilotThermalParamOptions o;
        o.imu = imu;
        return Unwrap(WriteArduPilotThermalParams(CubicsRadps(cubics_dps), o, comments));
      },
      py::arg("cubics_dps"), py::kw_only(), py::arg("imu") = 1, py::arg("comments") = std::vector<std::string>{},
      "ArduPilot INS_TCAL<imu>_* parameter file text from three axis cubics in deg/s (docs/explanation/flight-controller-export.md).");
}

}  // namespace gyrocomp::python
