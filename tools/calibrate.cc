// gyrocomp calibrate: every gyro, accelerometer (and PX4 barometer) of a flight log fitted and
// written as ONE parameter file the autopilot loads (docs/explanation/flight-controller-export.md, docs/reference/cli-contract.md). The work is the
// calibrate stage's (gyrocomp/calibrate/calibrate.h: sensors, block means, fit, projection,
// combining runs, validation, the parameter text); this file reads the options, prints the table
// and writes the files.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "calibrate_report.h"
#include "calibrate_sensor.h"
#include "gyrocomp/calibrate/calibrate.h"
#include "gyrocomp/report/report.h"
#include "result_json.h"

namespace gyrocomp::cli {
namespace {

using namespace calibrate;  // kCalibrateName, CalibrateArgs, Sensor, the outputs (calibrate_sensor.h)

int Run(const CalibrateArgs& a) {
  if (!(a.fit_rate_hz > 0.0) || !(a.min_span_c >= 0.0) || !(a.block_s > 0.0))
    return ReportError(kCalibrateName, InvalidArgument("--fit-rate must be > 0 Hz, --min-span >= 0 C and --block > 0 s"));
  Result<CalibrateResult> r = CalibrateLogs(a.inputs, a);
  if (!r.ok()) return ReportError(kCalibrateName, r.error());
  for (const std::string& n : r->notes) Note(kCalibrateName, n);
  std::cerr << r->BriefReport();
  if (!r->AnyCalibrated()) return ReportError(kCalibrateName, InvalidInput(a.input + ": no sensor could be calibrated (reasons above)"));
  const std::vector<Sensor>* sensors = &r->sensors;
  if (Status st = WriteModels(a, *sensors); !st.ok()) return ReportError(kCalibrateName, st.error());
  if (Status st = WriteText(a.output, r->parameter_text); !st.ok()) return ReportError(kCalibrateName, st.error());
  nlohmann::json j = {{"input", a.input}, {"format", a.format}, {"output", a.output}, {"fit_rate_hz", a.fit_rate_hz},
                      {"min_span_c", a.min_span_c}, {"optimised_for", a.optimise_for},
                      {"static_weight", a.static_weight}};
  j["models_dir"] = a.models_dir.empty() ? nlohmann::json(nullptr) : nlohmann::json(a.models_dir);
  j["inputs"] = a.inputs;
  j["validation_run"] = a.validation_path.empty() ? nlohmann::json(nullptr) : nlohmann::json(a.validation_path);
  j["block_s"] = a.block_s;
  j["sensors"] = nlohmann::json::array();
  for (const Sensor& s : *sensors) j["sensors"].push_back(SensorJson(a, s));
  if (!a.json_path.empty())
    if (Status st = WriteJson(a.json_path, j); !st.ok()) return ReportError(kCalibrateName, st.error());
  if (!a.report_path.empty()) {
    const ReportData report = BuildCalibrateReport(j, CubicCurves(*sensors));
    if (Status st = WriteText(a.report_path, RenderReportHtml(report)); !st.ok()) return ReportError(kCalibrateName, st.error());
  }
  Note(kCalibrateName, "-> " + a.output);
  return kExitOk;
}

Command MakeCalibrate(CLI::App& app) {
  auto a = std::make_shared<CalibrateArgs>();
  CLI::App* sub = app.add_subcommand(kCalibrateName, "Thermal calibration of every IMU sensor of a flight log, as one parameter file");
  sub->footer(
      "px4 (ULog): every sensor_gyro, sensor_accel and sensor_baro instance -> TC_G / TC_A / TC_B slots by\n"
      "  device_id, all four slots of each kind written (unused: ID 0), TC_x_ENABLE. QGroundControl format.\n"
      "ardupilot (DataFlash): every IMU, rotated back by AHRS_ORIENTATION and with any INS_TCAL correction the\n"
      "  log ran undone -> INS_TCAL1..3 ENABLE, TMIN, TMAX, ACC1..3, GYR1..3 (an IMU not calibrated: ENABLE 0).\n"
      "A sensor that cannot be calibrated (span < --min-span, too few rows) is listed with the reason.\n"
      "Expected error: per axis, the cubic's expected next-run RMS at steady temperature and on the run's warm-up\n"
      "  (the model's prediction band and the projection). --validation RUN: the cubics, with the firmware's\n"
      "  formula, and the full model scored on RUN (RMS of --block s means, mean removed).\n"
      "Example: gyrocomp calibrate -i heat.ulg --format px4 -o tc.params --models models/ --json cal.json\n"
      "           --validation cool.ulg --report cal.html");
  AddInputOption(sub, "-i,--input", &a->inputs,
                 "Flight log: PX4 ULog or ArduPilot DataFlash; repeated: runs of the same board, each sensor's cubics "
                 "averaged over them (models and bands from the first)")
      ->required();
  sub->add_option("--format", a->format, "px4 | ardupilot")->required()->check(CLI::IsMember({"px4", "ardupilot"}));
  AddOutputOption(sub, "-o,--output", &a->output, "Parameter file to write")->required();
  sub->add_option("--models", a->models_dir, "Directory for each sensor's model file (<type><instance>.json) for apply / validate / export");
  AddOutputOption(sub, "--json", &a->json_path, "Write the per-sensor summary as JSON ('-' = stdout)");
  AddInputOption(sub, "--validation", &a->validation_path,
                 "A second log of the same board (same format as -i): every exported cubic (firmware formula) and "
                 "the full model scored on it, per axis");
  AddOutputOption(sub, "--report", &a->report_path, "Write an HTML report to FILE (self-contained, opens offline)");
  sub->add_option("--block", a->block_s, "--validation: residual block means, s")->capture_default_str();
  sub->add_option("--fit-rate", a->fit_rate_hz, "Rows per second the fit sees (block means), Hz")->capture_default_str();
  sub->add_option("--optimise-for", a->optimise_for,
                  "What the exported cubic is optimised for: steady (dT/dt = 0, the static curve) | warm-up (the state the "
                  "run had while heating, at each temperature) | both (their mean)")
      ->check(CLI::IsMember({"steady", "warm-up", "both"}))
      ->capture_default_str();
  sub->add_option("--static-weight", a->static_weight,
                  "How the static curve is estimated: auto (per axis, the one of the two below with the lower "
                  "expected next-run error: a left-out dT/dt gain against the holds' information) | temperature (each "
                  "temperature alike: the run's data with the model's dynamic part removed, in 2000 equal temperature "
                  "bins, as PX4's script bins) | time (the fitted model's curve, every sample alike)")
      ->check(CLI::IsMember({"auto", "temperature", "time"}))
      ->capture_default_str();
  sub->add_option("--min-span", a->min_span_c, "Smallest temperature span calibrated, deg C (ArduPilot's TEMP_RANGE_MIN)")
      ->capture_default_str();
  return {sub, [a] {
            a->input = a->inputs.front();
            return Run(*a);
          }};
}

const CommandRegistrar kCalibrateRegistrar(kCalibrateName, 67, &MakeCalibrate);

}  // namespace
}  // namespace gyrocomp::cli
