// gyrocomp export: put a drift model on the device (docs/explanation/flight-controller-export.md). PX4 and ArduPilot
// parameter files (the model projected onto the autopilot's cubic in T, with the cost measured)
// or a generated C99 evaluator of the full model with the causal dT/dt estimator inside.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "gyrocomp/core/units.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/axis_cubics.h"
#include "gyrocomp/export/c_export.h"
#include "gyrocomp/export/cubic_score.h"
#include "gyrocomp/export/param_export.h"
#include "gyrocomp/export/static_weight.h"
#include "gyrocomp/export/thermal_cubic.h"
#include "result_json.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kExportName = "export";
constexpr double kRadPerDeg = std::numbers::pi / 180.0;

struct ExportArgs {
  std::vector<std::string> model_paths;
  std::string format;
  std::string output;
  std::string json_path;
  std::optional<long long> device_id;
  std::optional<int> index;
  std::optional<int> file_instance;  // the instance the model files were fitted on ("sensor")
  std::string c_unit = "dps";
  LogOptions log;               // optional calibration run (-i): projection cost
  std::string validation_path;  // optional validation run, same columns
  // px4 / ardupilot: how the static curve is estimated (static_weight.h): auto (per axis, the
  // estimator with the lower expected next-run error; needs -i, else time), temperature (each
  // temperature of the -i run alike; needs -i), time (the model's own curve).
  std::string static_weight = "auto";
};

// Every -m file holds one or more axes (model file v2: one model per rate column); the axes are
// taken in the order given (x, y, z for the autopilots).
// `device_id` receives the gyro's device id recorded in the files (fitted on a PX4 ULog), when
// they record one; files that disagree are an error.
Result<std::vector<AxisDriftModel>> LoadAxes(const std::vector<std::string>& paths, std::vector<std::string>* sources,
                                             std::optional<std::uint32_t>* device_id, std::optional<int>* instance) {
  std::vector<AxisDriftModel> axes;
  for (const std::string& p : paths) {
    Result<DriftModelSet> set = LoadDriftModelSet(p);
    if (!set.ok()) return set.error();
    if (set->device_id && *device_id && **device_id != *set->device_id)
      return InvalidInput(p + ": device_id " + std::to_string(*set->device_id) + " differs from " +
                          std::to_string(**device_id) + " of " + paths.front() + ": models of different gyros");
    if (set->device_id) *device_id = set->device_id;
    if (set->sensor) *instance = set->sensor->instance;  // the log's instance (model file "sensor")
    for (DriftModel& m : set->axes) {
      if (m.unit != "deg/s")
        return InvalidInput(p + ": axis '" + m.rate_col + "' predicts '" + m.unit + "', not deg/s; export needs "
                            "a rate model (fit --target rate or drift-mode)");
      axes.push_back({m.rate_col, std::move(m)});
      sources->push_back(p);
    }
  }
  return axes;
}

nlohmann::json WeightJson(const AxisCubic& c) {
  nlohmann::json j = {{"static_weight", c.weight}};
  if (!c.weight_reason.empty()) j["reason"] = c.weight_reason;
  if (c.weight_choice) {
    auto e = [](const StaticEstimatorError& x) {
      return nlohmann::json{{"total_rms_dps", x.total_rms}, {"rate_gain_rms_dps", x.rate_gain_rms}, {"noise_rms_dps", x.noise_rms}};
    };
    j["time"] = e(c.weight_choice->time);
    j["temperature"] = e(c.weight_choice->temperature);
    j["unidentified_rate_gain_rms"] = c.weight_choice->rate_gain_rms;
    j["reason"] = c.weight_choice->reason;
  }
  return j;
}

nlohmann::json ConditionJson(const CubicConditionError& e) {
  return {{"total_rms_dps", e.total_rms}, {"total_rms_rad_s", e.total_rms * kRadPerDeg},
          {"projection_rms_dps", e.projection_rms}, {"band_sd_rms_dps", e.band_sd_rms}, {"samples", e.num_samples}};
}

nlohmann::json ExpectedJson(const AxisCubic& c) {
  if (!c.expected) return {{"reason", c.expected_reason}};
  nlohmann::json j = {{"band_level", c.expected->level}, {"steady", ConditionJson(c.expected->steady)}};
  j["warm_up"] = c.expected->warm_up ? ConditionJson(*c.expected->warm_up) : nlohmann::json(nullptr);
  if (!c.expected->warm_up) j["warm_up_reason"] = "needs the calibration run (-i) with heating samples";
  return j;
}

nlohmann::json CostJson(const std::optional<CubicProjectionCost>& c) {
  if (!c) return nullptr;
  return {{"n_samples", c->num_samples}, {"rms_dps", c->rms}, {"max_abs_dps", c->max_abs},
          {"rms_rad_s", c->rms * kRadPerDeg}, {"model_span_dps", c->model_span}};
}

// The record's temperature as DriftInputs, read with the shared log options.
Result<GyroLog> ReadRun(const LogOptions& options) {
  Result<LogSpec> spec = ToLogSpec(options);
  if (!spec.ok()) return spec.error();
  spec->temp_required = true;
  spec->keep_cols.emplace();  // only the log: time, rates, temperature (memory)
  Result<LoadedLog> loaded = LoadLog(kExportName, options, *spec);
  if (!loaded.ok()) return loaded.error();
  return std::move(loaded->log);
}

// Reads the calibration (-i) and validation runs given, then projects every axis onto one shared
// range with its static curve and measures the cost on those runs (ExportAxisCubics).
Result<std::vector<AxisCubic>> ProjectAxes(const ExportArgs& a, const std::vector<AxisDriftModel>& axes) {
  std::optional<GyroLog> cal, val;
  if (!a.log.input.empty()) {
    auto r = ReadRun(a.log);
    if (!r.ok()) return r.error();
    cal = std::move(*r);
  }
  if (!a.validation_path.empty()) {
    LogOptions v = a.log;
    v.input = a.validation_path;
    auto r = ReadRun(v);
    if (!r.ok()) return r.error();
    val = std::move(*r);
  }
  AxisCubicsOptions o;
  o.static_weight = *ParseStaticWeight(a.static_weight);
  return ExportAxisCubics(axes, cal ? &*cal : nullptr, val ? &*val : nullptr, o);
}

std::vector<std::string> ParamComments(const ExportArgs& a, const std::vector<AxisDriftModel>& axes,
                                       const std::vector<std::string>& src, const std::vector<AxisCubic>& costs) {
  std::vector<std::string> c = {
      "Gyro thermal compensation generated by gyrocomp export --format " + a.format + " (docs/explanation/flight-controller-export.md)",
      "Rates: the models predict deg/s (the log's unit was converted to deg/s when it was read);",
      "  exported in rad/s = deg/s x pi/180. Temperatures in deg C, clamped to [TMIN, TMAX].",
      "Each axis's model projected by least squares onto a cubic in T over [TMIN, TMAX]",
      "  (uniform temperature grid, dT/dt = 0), or, where its static curve says temperature (--static-weight),",
      "  the -i run's static curve with each temperature alike; cost = RMS(full model - cubic) in deg/s:"};
  static constexpr const char* kAxis[3] = {"x", "y", "z"};
  for (std::size_t k = 0; k < axes.size(); ++k) {
    std::ostringstream s;
    s << "  " << kAxis[k] << ": " << axes[k].axis << " of " << src[k] << " (" << DriftModelKindName(axes[k].model.kind) << ", "
      << DriftInputSetName(axes[k].model.inputs) << ")";
    if (costs[k].calibration) s << "; calibration run " << costs[k].calibration->rms;
    if (costs[k].validation) s << "; validation run " << costs[k].validation->rms;
    if (!costs[k].calibration && !costs[k].validation) s << "; cost not measured (give -i / --validation)";
    c.push_back(s.str());
    std::ostringstream e;
    const auto& x = costs[k].expected;
    e << "     expected next-run error of the cubic (RMS, deg/s; band + projection, docs/explanation/flight-controller-export.md): ";
    if (!x) {
      e << "n/a, " << costs[k].expected_reason;
    } else {
      e << "steady " << x->steady.total_rms << ", warm-up ";
      if (x->warm_up) e << x->warm_up->total_rms << " (the -i run's heating)";
      else e << "n/a (give the calibration run with -i)";
    }
    c.push_back(e.str());
    std::ostringstream w;
    w << "     static curve: " << costs[k].weight;
    if (costs[k].weight_choice) w << " (auto: " << costs[k].weight_choice->reason << ")";
    else if (!costs[k].weight_reason.empty()) w << " (" << costs[k].weight_reason << ")";
    c.push_back(w.str());
  }
  return c;
}

int RunParams(const ExportArgs& a, const std::vector<AxisDriftModel>& axes, const std::vector<std::string>& src,
              nlohmann::json* j) {
  if (axes.size() != 3)
    return ReportError(kExportName, InvalidArgument("--format " + a.format + " needs three axis models (one file with three "
                                              "axes, or -m x.json -m y.json -m z.json), got " +
                                              std::to_string(axes.size())));
  auto costs = ProjectAxes(a, axes);
  if (!costs.ok()) return ReportError(kExportName, costs.error());
  ThreeAxisCubics radps;
  for (int k = 0; k < 3; ++k) radps[k] = (*costs)[k].cubic_dps.Scaled(kRadPerDeg);
  const auto comments = ParamComments(a, axes, src, *costs);
  Result<std::string> text = InternalError("unreachable");
  // --index follows the gyro instance when it is not given: --instance of -i, else the instance
  // the model file records (PX4 slot i = instance; ArduPilot INS_TCAL<n>, n = instance + 1).
  const std::optional<int> instance = a.log.instance ? a.log.instance : a.file_instance;
  if (!a.index && instance && *instance > (a.format == "px4" ? 3 : 2))
    return ReportError(kExportName, InvalidArgument("gyro instance " + std::to_string(*instance) + " has no " + a.format +
                                              " slot of the same number; choose one with --index"));
  if (a.format == "px4") {
    Px4ThermalParamOptions o;
    o.index = a.index.value_or(instance.value_or(0));
    if (a.device_id) {
      if (*a.device_id <= 0 || *a.device_id > 0xFFFFFFFFLL)
        return ReportError(kExportName, InvalidArgument("--device-id: must be in 1..4294967295"));
      o.device_id = static_cast<std::uint32_t>(*a.device_id);
    }
    text = WritePx4ThermalParams(radps, o, comments);
  } else {
    ArduPilotThermalParamOptions o;
    o.imu = a.index.value_or(instance.value_or(0) + 1);
    text = WriteArduPilotThermalParams(radps, o, comments);
  }
  if (!text.ok()) return ReportError(kExportName, text.error());
  if (Status s = WriteText(a.output.empty() ? "-" : a.output, *text); !s.ok()) return ReportError(kExportName, s.error());
  nlohmann::json ax = nlohmann::json::array();
  for (int k = 0; k < 3; ++k) {
    const TemperatureCubic& c = (*costs)[k].cubic_dps;
    ax.push_back({{"model_file", src[k]}, {"rate_col", axes[k].axis}, {"model", DriftSummaryJson(axes[k].model.summary)},
                  {"cubic_dps", {{"ref_temp_c", c.ref_temp_c}, {"coeff", c.coeff}}},
                  {"cost_calibration", CostJson((*costs)[k].calibration)},
                  {"cost_validation", CostJson((*costs)[k].validation)},
                  {"expected_error", ExpectedJson((*costs)[k])}, {"static_weight", WeightJson((*costs)[k])}});
  }
  (*j)["axes"] = ax;
  (*j)["temp_min_c"] = radps[0].temp_min_c;
  (*j)["temp_max_c"] = radps[0].temp_max_c;
  (*j)["ref_temp_c"] = radps[0].ref_temp_c;
  return kExitOk;
}

int RunC(const ExportArgs& a, const std::vector<AxisDriftModel>& axes, const std::vector<std::string>& src,
         nlohmann::json* j) {
  if (a.output.empty() || a.output == "-")
    return ReportError(kExportName, InvalidArgument("--format c needs -o DIR/NAME (writes DIR/NAME.h and DIR/NAME.c)"));
  const std::filesystem::path out(a.output);
  CExportOptions o;
  o.prefix = out.filename().string();
  if (a.c_unit == "rads") {
    o.output_scale = kRadPerDeg;
    o.output_unit = "rad/s";
  } else if (a.c_unit != "dps") {
    return ReportError(kExportName, InvalidArgument("--c-unit " + a.c_unit + ": expected dps or rads"));
  }
  for (const std::string& p : a.model_paths) o.comments.push_back("model: " + p);
  Result<GeneratedC> gen = GenerateCEvaluator(axes, o);
  if (!gen.ok()) return ReportError(kExportName, gen.error());
  const std::filesystem::path dir = out.parent_path();
  if (Status s = WriteText((dir / gen->header_name).string(), gen->header); !s.ok()) return ReportError(kExportName, s.error());
  if (Status s = WriteText((dir / gen->source_name).string(), gen->source); !s.ok()) return ReportError(kExportName, s.error());
  nlohmann::json ax = nlohmann::json::array();
  for (std::size_t k = 0; k < axes.size(); ++k)
    ax.push_back({{"model_file", src[k]}, {"rate_col", axes[k].axis}, {"model", DriftSummaryJson(axes[k].model.summary)},
                  {"thermal_state", DriftInputSetName(axes[k].model.inputs)},
                  {"out_of_range", OutOfRangePolicyName(axes[k].model.out_of_range)}});
  (*j)["axes"] = ax;
  (*j)["files"] = {(dir / gen->header_name).string(), (dir / gen->source_name).string()};
  (*j)["unit"] = o.output_unit;
  return kExitOk;
}

int Run(const ExportArgs& args) {
  std::vector<std::string> src;
  std::optional<std::uint32_t> file_device_id;
  std::optional<int> file_instance;
  auto axes = LoadAxes(args.model_paths, &src, &file_device_id, &file_instance);
  if (!axes.ok()) return ReportError(kExportName, axes.error());
  ExportArgs a = args;  // --device-id, else the id the model file carries (fitted on a ULog)
  a.file_instance = file_instance;
  if (!a.device_id && file_device_id) a.device_id = *file_device_id;
  nlohmann::json j;
  j["format"] = a.format;
  j["output"] = a.output.empty() ? "-" : a.output;
  const int rc = a.format == "c" ? RunC(a, *axes, src, &j) : RunParams(a, *axes, src, &j);
  if (rc != kExitOk) return rc;
  if (!a.json_path.empty())
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kExportName, s.error());
  return kExitOk;
}

Command MakeExport(CLI::App& app) {
  auto a = std::make_shared<ExportArgs>();
  CLI::App* sub = app.add_subcommand(kExportName, "Export drift models for a flight controller: PX4 / ArduPilot parameters or C code");
  sub->footer(
      "px4: QGroundControl parameter file (TC_G_ENABLE, TC_G<i>_ID/TREF/TMIN/TMAX/X0..X3_0..2, rad/s);\n"
      "  needs the gyro's device_id (from the model file when it was fitted on a ULog, else --device-id) and three axes: one file (fit --rate-col gx,gy,gz)\n"
      "  or -m x -m y -m z.\n"
      "ardupilot: .param file (INS_TCAL<n>_ENABLE/TMIN/TMAX/GYR1..3_X/Y/Z: x1e6, rad/s, about 35 C).\n"
      "  Both are cubics in T: each model is projected onto one; with -i CAL (and --validation RUN,\n"
      "  same columns) the cost RMS(full model - cubic) is measured and written in the header.\n"
      "c: -o DIR/NAME writes NAME.h and NAME.c (C99, no allocation, -DNAME_USE_FLOAT for float):\n"
      "  the full model per axis with its causal thermal state; same numbers as apply --causal.\n"
      "Example: gyrocomp export -m x.json -m y.json -m z.json --format px4 --device-id 2293768 -o tc.params");
  AddInputOption(sub, "-m,--model", &a->model_paths, "Model file(s) written by gyrocomp fit: their axes in order (x, y, z)")
      ->required();
  sub->add_option("--format", a->format, "px4 | ardupilot | c")->required()->check(CLI::IsMember({"px4", "ardupilot", "c"}));
  // For c, -o is a stem: NAME.h and NAME.c are declared when written (WriteText).
  sub->add_option("-o,--output", a->output, "Output file ('-' or none: stdout); for c: DIR/NAME");
  AddOutputOption(sub, "--json", &a->json_path, "Write a summary as JSON to FILE ('-' = stdout)");
  sub->add_option("--device-id", a->device_id, "px4: TC_G<i>_ID, the gyro's device_id (sensor_gyro.device_id); default: the one the model file carries when it was fitted on a PX4 ULog");
  sub->add_option("--index", a->index, "px4: slot i of TC_G<i> (0..3); ardupilot: IMU n of INS_TCAL<n> (1..3); default: from the gyro instance (--instance, else the model file's sensor.instance): i = instance, n = instance + 1; else 0 / 1");
  sub->add_option("--c-unit", a->c_unit, "c: unit of rate_in/rate_out, dps or rads")->capture_default_str();
  AddLogOptions(sub, &a->log, /*input_required=*/false);
  AddInputOption(sub, "--validation", &a->validation_path, "px4/ardupilot: a validation run (same columns as -i) for the cost");
  sub->add_option("--static-weight", a->static_weight,
                  "px4/ardupilot: the static curve exported: auto (per axis, the estimator below with the lower expected "
                  "next-run error; time without -i) | temperature (the -i run, each temperature alike, the model's dynamic "
                  "part removed) | time (the model's own curve)")
      ->check(CLI::IsMember({"auto", "temperature", "time"}))
      ->capture_default_str();
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kExportRegistrar(kExportName, 67, &MakeExport);

}  // namespace
}  // namespace gyrocomp::cli
