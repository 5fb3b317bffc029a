// gyrocomp.project_onto_cubic, px4_thermal_params, ardupilot_thermal_params (the export
// stage, include/gyrocomp/export/). The three-axis convenience export_params is Python
// (python/gyrocomp/__init__.py).
#include "bindings.h"

#include "gyrocomp/core/units.h"
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

}  // namespace

void BindExport(py::module_& m) {
  m.def(
      "generate_c",
      [](const std::vector<DriftModel>& models, std::vector<std::string> axes, const py::kwargs& kwargs) {
        Kwargs kw(kwargs, "generate_c");
        CExportOptions o;
        kw.Get("prefix", &o.prefix);
        kw.Get("output_scale", &o.output_scale);
        kw.Get("output_unit", &o.output_unit);
        kw.Get("comments", &o.comments);
        kw.Done();
        if (!axes.empty() && axes.size() != models.size())
          throw py::value_error("generate_c(): " + std::to_string(axes.size()) + " axis names for " +
                                std::to_string(models.size()) + " models");
        std::vector<AxisDriftModel> in;
        for (std::size_t k = 0; k < models.size(); ++k)
          in.push_back({axes.empty() ? models[k].summary.target_name : axes[k], models[k]});
        const GeneratedC g = Unwrap(GenerateCEvaluator(in, o));
        return py::dict(py::arg("header_name") = g.header_name, py::arg("header") = g.header,
                        py::arg("source_name") = g.source_name, py::arg("source") = g.source);
      },
      py::arg("models"), py::arg("axes") = std::vector<std::string>{},
      "The dependency-free C99 evaluator of drift models (one per axis), as `gyrocomp export --format c`: "
      "a dict with header_name, header, source_name, source. Keywords (CExportOptions): prefix, output_scale, "
      "output_unit, comments; axes defaults to each model's target name.");

  m.def(
      "project_onto_cubic",
      [](const DriftModel& model, const py::kwargs& kwargs) {
        Kwargs kw(kwargs, "project_onto_cubic");
        CubicProjectionOptions o;
        kw.Get("grid_points", &o.grid_points);
        kw.Get("temp_min_c", &o.temp_min_c);
        kw.Get("temp_max_c", &o.temp_max_c);
        kw.Get("ref_temp_c", &o.ref_temp_c);
        kw.Done();
        return CubicDict(Unwrap(WithoutGil([&] { return ProjectOntoCubic(model, o); })));
      },
      py::arg("model"), "Least-squares cubic in T (deg/s) of a drift model (CubicProjectionOptions as keywords).");

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
