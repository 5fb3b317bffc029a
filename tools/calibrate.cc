// gyrocomp calibrate: every gyro, accelerometer (and PX4 barometer) of a flight log fitted and
// written as ONE parameter file the autopilot loads (docs/explanation/flight-controller-export.md, docs/reference/cli-contract.md). The work is the
// calibrate stage's (gyrocomp/calibrate/calibrate.h: sensors, block means, fit, projection,
// combining runs, validation, the parameter text); this file reads the options, prints the table
// and writes the files.
#include <cmath>
#include <iostream>
#include <set>
#include <sstream>
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "console.h"
#include "calibrate_report.h"
#include "calibrate_sensor.h"
#include "gyrocomp/calibrate/calibrate.h"
#include "gyrocomp/core/units.h"
#include "gyrocomp/report/report.h"
#include "result_json.h"

namespace gyrocomp::cli {
namespace {

using namespace calibrate;  // kCalibrateName, CalibrateArgs, Sensor, the outputs (calibrate_sensor.h)

// A sensor's figure in the unit a person reads: gyro in mdps or deg/s, accel in mg, baro in Pa.
std::string Readable(const Sensor& s, double firmware_value) {
  if (s.type == "gyro") return RateRadS(firmware_value);
  if (s.type == "accel") return Figure(units::MetresPerSec2ToMilliG(firmware_value)) + " mg";
  return Figure(firmware_value) + " " + s.unit;
}

// RMS over a sensor's axes of per-axis figures.
double AxisRms(const std::vector<double>& per_axis) {
  double sum = 0.0;
  for (double v : per_axis) sum += v * v;
  return per_axis.empty() ? NAN : std::sqrt(sum / static_cast<double>(per_axis.size()));
}

// The drift the run shows without compensation: per axis the RMS of its block means about their
// mean (firmware unit), RMS over the axes.
double UncompensatedRms(const Sensor& s) {
  std::vector<double> per_axis;
  for (const std::vector<double>& v : s.values) {
    if (v.empty()) continue;
    double mean = 0.0;
    for (double x : v) mean += x;
    mean /= static_cast<double>(v.size());
    double ss = 0.0;
    for (double x : v) ss += (x - mean) * (x - mean);
    per_axis.push_back(std::sqrt(ss / static_cast<double>(v.size())));
  }
  return AxisRms(per_axis);
}

// The expected next-run error of the exported cubics (the condition --optimise-for chose), RMS
// over the axes, firmware unit (CubicExpectedError is in the model's unit); NaN without a band.
double ExpectedRms(const Sensor& s, bool warm_up) {
  std::vector<double> per_axis;
  for (const std::optional<CubicExpectedError>& e : s.expected) {
    if (!e) return NAN;
    const double model_unit = warm_up && e->warm_up ? e->warm_up->total_rms : e->steady.total_rms;
    per_axis.push_back(model_unit / s.to_model);
  }
  return AxisRms(per_axis);
}

// Per log, where the vehicle was still: segments (start, length, temperature span) and the parts
// rejected with the reason.
nlohmann::json LogsJson(const CalibrateResult& r) {
  nlohmann::json out = nlohmann::json::array();
  for (const CalibrateResult::LogStill& l : r.logs) {
    const StillDetection& d = l.detection;
    nlohmann::json segments = nlohmann::json::array(), rejected = nlohmann::json::array();
    for (const StillSegment& s : d.segments)
      segments.push_back({{"start_s", s.start_s}, {"length_s", s.length_s}, {"temp_min_c", s.temp_min_c}, {"temp_max_c", s.temp_max_c}});
    for (const RejectedPart& p : d.rejected) rejected.push_back({{"start_s", p.start_s}, {"length_s", p.length_s}, {"reason", p.reason}});
    out.push_back({{"path", l.path}, {"state", l.state}, {"still_s", d.still_s}, {"total_s", d.total_s}, {"gyro_noise_rad_s", d.gyro_noise_rad_s},
                   {"accel_noise_m_s2", d.accel_noise_m_s2}, {"still_segments", segments}, {"rejected", rejected}});
  }
  return out;
}

// True when the logs are one log still throughout (the single-run path: no still lines).
bool StillThroughout(const CalibrateResult& r) {
  return r.logs.size() == 1 && r.logs[0].detection.rejected.empty() && r.logs[0].detection.segments.size() == 1;
}

// The default summary: a header (what was read), one line per sensor (uncompensated drift against
// the expected next-run error of its exported cubic), the next step when a sensor was skipped.
// The pooled sensors that kept a dT/dt term or a lag, which a firmware cubic cannot carry: what
// the exported cubic leaves in the condition it was not made for (Sensor::warm_up_rms for the
// steady cubic, steady_rms otherwise, RMS over the axes), one line for all; "" when none. A
// sensor is named only where that is above both the curve's own 1 sigma and 5 % of the drift its
// first log shows uncompensated: a smaller trade is below what the fit can tell or the file removes.
// Two runs of different directions cannot both be matched by one cubic
// (docs/explanation/accuracy-calibration.md, "Could any cubic be never worse in both directions?").
std::string TradeLine(const CalibrateArgs& a, const CalibrateResult& r) {
  const bool steady = a.optimise_for == "steady";
  std::string names, figures;
  int lags = 0, terms = 0;
  for (const Sensor& s : r.sensors) {
    if (!s.calibrated() || s.fit != "pooled" || s.heating_state_kind.empty()) continue;
    const double left = AxisRms(steady ? s.warm_up_rms : s.steady_rms);
    if (!(left > AxisRms(s.curve_sd) && left > 0.05 * UncompensatedRms(s))) continue;
    names += (names.empty() ? "" : ", ") + s.type + " " + std::to_string(s.instance);
    figures += (figures.empty() ? "" : ", ") + Readable(s, left);
    ++terms;
    lags += s.temp_lag_s > 0.0;
  }
  if (terms == 0) return "";
  const std::string kept = names + " kept " + (lags == terms ? "a lag" : lags == 0 ? "a dT/dt term" : "a dT/dt term or a lag");
  if (steady)
    return kept + " a firmware cubic cannot carry: the steady cubic leaves " + figures +
           " while heating at the logs' rate (--optimise-for warm-up trades that against cooling)";
  return kept + ": the cubic optimised for " + a.optimise_for + " leaves " + figures +
         " when the temperature is steady, more while cooling";
}

// Logs in which the vehicle moves, or several logs: a line on the still time, and per sensor
// what the logs identify (pooled fit) and which log would help.
// --verbose prints the full table (projection cost, static weighting, validation per axis).
void PrintSummary(const CalibrateArgs& a, const CalibrateResult& r) {
  int calibrated = 0;
  double lo = INFINITY, hi = -INFINITY;
  for (const Sensor& s : r.sensors) {
    if (!s.calibrated()) continue;
    ++calibrated;
    lo = std::min(lo, s.temp_min_c);
    hi = std::max(hi, s.temp_max_c);
  }
  std::string head = std::to_string(r.inputs.size()) + (r.inputs.size() == 1 ? " log (" : " logs (") + a.input +
                     (r.inputs.size() > 1 ? ", ..." : "") + "), " + a.format + ": " + std::to_string(calibrated) +
                     " of " + std::to_string(r.sensors.size()) + " sensors calibrated";
  if (calibrated > 0) head += " over " + Figure(lo) + " .. " + Figure(hi) + " C";
  Headline(kCalibrateName, head);
  const bool pooled = !StillThroughout(r);
  if (pooled) {
    double still = 0.0, total = 0.0;
    std::size_t segments = 0;
    for (const CalibrateResult::LogStill& l : r.logs) still += l.detection.still_s, total += l.detection.total_s, segments += l.detection.segments.size();
    Line("still: " + Figure(still / 60.0) + " of " + Figure(total / 60.0) + " min in " + std::to_string(segments) +
         " segment(s) over " + std::to_string(r.logs.size()) + " log(s) (--verbose or --json: per log)");
  }
  const bool warm_up = a.optimise_for == "warm-up";
  bool skipped = false;
  std::set<std::string> help;  // what another log would add, each text once
  for (const Sensor& s : r.sensors) {
    std::ostringstream line;
    line << s.type << " " << s.instance;
    if (s.device_id) line << " (id " << *s.device_id << ")";
    line << ": ";
    if (!s.calibrated()) {
      skipped = true;
      line << WarnColour("skipped") << ", " << s.reason;
      // Pooled (flights, several logs): which log would help; a single chamber run's line as before.
      if (pooled && !s.identification.would_help.empty()) help.insert(s.identification.would_help);
    } else if (s.fit == "pooled") {
      // The curve's own 1 sigma beside the drift; what the logs identify is in --verbose.
      line << "drift " << Readable(s, UncompensatedRms(s)) << " uncompensated (first log's still rows), curve 1 sigma "
           << Readable(s, AxisRms(s.curve_sd)) << ", pooled over " << s.runs_combined << " log(s)";
      if (!s.identification.would_help.empty()) help.insert(s.identification.would_help);
    } else {
      const double before = UncompensatedRms(s), after = ExpectedRms(s, warm_up);
      line << "drift " << Readable(s, before) << " uncompensated -> " << Readable(s, after)
           << " expected on the next run";
      if (before > 0.0 && std::isfinite(after)) line << " (" << Figure(after / before, 2) << "x)";
      if (!std::isfinite(after)) line << " (no band: " << s.band_reason << ")";
      if (s.validation && s.validation->reason.empty()) {
        line << "; on the validation run " << Readable(s, AxisRms(s.validation->raw)) << " -> "
             << Readable(s, AxisRms(s.validation->cubic));
      }
    }
    Line(line.str());
  }
  if (const std::string trade = TradeLine(a, r); !trade.empty()) Line(trade);
  for (const std::string& h : help) Line("would help: " + h);
  if (skipped) {
    Line("next: a skipped sensor needs a run whose temperature spans at least --min-span (" + Figure(a.min_span_c) +
         " C)" + (pooled ? " inside one log and --min-still (" + Figure(a.min_still_s) + " s) of still time" : " with enough rows") +
         "; see the reason beside it");
  }
}

int Run(const CalibrateArgs& a) {
  if (!(a.fit_rate_hz > 0.0) || !(a.min_span_c >= 0.0) || !(a.block_s > 0.0) || !(a.min_still_s >= 0.0) || !(a.still_rate_hz > 0.0))
    return ReportError(kCalibrateName, InvalidArgument("--fit-rate and --still-rate must be > 0 Hz, --min-span >= 0 C, --min-still >= 0 s and --block > 0 s"));
  Result<CalibrateResult> r = CalibrateLogs(a.inputs, a);
  if (!r.ok()) return ReportError(kCalibrateName, r.error());
  for (const std::string& n : r->notes) Note(kCalibrateName, n);
  const bool pooled = std::any_of(r->sensors.begin(), r->sensors.end(), [](const Sensor& s) { return s.fit == "pooled"; });
  if (pooled && a.static_weight_given)
    Note(kCalibrateName, "--static-weight ignored: it does not apply to a pooled fit (several logs, or a log not still "
                         "throughout: one cubic over the still rows, no drift model whose static curve to weight)");
  const bool any_term = std::any_of(r->sensors.begin(), r->sensors.end(), [](const Sensor& s) { return !s.heating_state_kind.empty(); });
  if (pooled && a.optimise_for != "steady" && !any_term)
    Note(kCalibrateName, "--optimise-for " + a.optimise_for + " changes nothing here: no sensor kept a dT/dt term or a lag, "
                         "so every cubic is the steady curve");
  if (a.verbose) std::cerr << r->BriefReport();
  else PrintSummary(a, *r);
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
  j["min_still_s"] = a.min_still_s;
  j["logs"] = LogsJson(*r);
  j["sensors"] = nlohmann::json::array();
  for (const Sensor& s : *sensors) j["sensors"].push_back(SensorJson(a, s));
  if (!a.json_path.empty())
    if (Status st = WriteJson(a.json_path, j); !st.ok()) return ReportError(kCalibrateName, st.error());
  if (!a.report_path.empty()) {
    const ReportData report = BuildCalibrateReport(j, *sensors);
    if (Status st = WriteText(a.report_path, RenderReportHtml(report)); !st.ok()) return ReportError(kCalibrateName, st.error());
  }
  if (a.verbose) Note(kCalibrateName, "-> " + a.output);
  else Wrote({a.output, a.json_path, a.report_path, a.models_dir});
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
      "Every log goes through a still detector (gyro and accel variance against the sensor's own noise; rows the\n"
      "  log marks armed or not landed are not used); only still rows feed the fit. One log still throughout (a\n"
      "  chamber run): the drift model projected onto the cubic. Several logs or flights: one least-squares\n"
      "  cubic over all still rows, a constant per log (gyro, baro) or per still segment (accel: the attitude's\n"
      "  share of gravity); --optimise-for adds the kept dT/dt gain or lag at the logs' heating state (steady:\n"
      "  none), --static-weight does not apply to it (a note says so when given).\n"
      "  A board rotation or a log rate that differs between the logs is noted, not refused.\n"
      "A sensor that cannot be calibrated (span < --min-span, still time < --min-still, too few rows) is listed\n"
      "  with the reason and which log would help.\n"
      "Expected error: per axis, the cubic's expected next-run RMS at steady temperature and on the run's warm-up\n"
      "  (the model's prediction band and the projection). --validation RUN: the cubics, with the firmware's\n"
      "  formula, and the full model scored on RUN (RMS of --block s means, mean removed).\n"
      "Example: gyrocomp calibrate -i heat.ulg --format px4 -o tc.params --models models/ --json cal.json\n"
      "           --validation cool.ulg --report cal.html");
  AddInputOption(sub, "-i,--input", &a->inputs,
                 "Flight log: PX4 ULog or ArduPilot DataFlash, a chamber run or an ordinary flight; repeated: logs of "
                 "the same board, one cubic fitted to all their still rows with a constant per log")
      ->required();
  sub->add_option("--format", a->format, "px4 | ardupilot")->required()->check(CLI::IsMember({"px4", "ardupilot"}));
  AddOutputOption(sub, "-o,--output", &a->output, "Parameter file to write")->required();
  sub->add_option("--models", a->models_dir, "Directory for each sensor's model file (<type><instance>.json) for apply / validate / export");
  AddOutputOption(sub, "--json", &a->json_path, "Write the per-sensor summary as JSON ('-' = stdout)");
  AddInputOption(sub, "--validation", &a->validation_path,
                 "A second log of the same board (same format as -i): every exported cubic (firmware formula) and "
                 "the full model scored on it, per axis");
  AddOutputOption(sub, "--report", &a->report_path, "Write an HTML report to FILE (self-contained, opens offline)");
  sub->add_flag("-v,--verbose", a->verbose,
                "The full table per sensor and axis (one run: projection cost, expected error steady and warm-up, static "
                "weighting; pooled: lag, dT/dt gain, curve 1 sigma, what the cubic leaves steady and at the heating state)");
  sub->add_option("--block", a->block_s, "--validation: residual block means, s")->capture_default_str();
  sub->add_option("--fit-rate", a->fit_rate_hz, "Rows per second the fit sees (block means), Hz")->capture_default_str();
  sub->add_option("--optimise-for", a->optimise_for,
                  "What the exported cubic is optimised for: steady (dT/dt = 0, the static curve) | warm-up (the state the "
                  "run had while heating, at each temperature) | both (their mean). Pooled (several logs): the shared "
                  "curve with the kept dT/dt gain or lag at the state the logs' still rows had while heating; a sensor "
                  "with neither gets the steady curve")
      ->check(CLI::IsMember({"steady", "warm-up", "both"}))
      ->capture_default_str();
  CLI::Option* static_weight = sub->add_option("--static-weight", a->static_weight,
                  "How the static curve is estimated: auto (per axis, the one of the two below with the lower "
                  "expected next-run error: a left-out dT/dt gain against the holds' information) | temperature (each "
                  "temperature alike: the run's data with the model's dynamic part removed, in 2000 equal temperature "
                  "bins, as PX4's script bins) | time (the fitted model's curve, every sample alike). One log still "
                  "throughout only: a pooled fit (several logs) ignores it, with a note")
      ->check(CLI::IsMember({"auto", "temperature", "time"}))
      ->capture_default_str();
  sub->add_option("--min-span", a->min_span_c, "Smallest temperature span calibrated, deg C (ArduPilot's TEMP_RANGE_MIN)")
      ->capture_default_str();
  sub->add_option("--min-still", a->min_still_s, "Least still time of a sensor over all the logs, s; less: no entry for it")
      ->capture_default_str();
  sub->add_option("--still-threshold", a->still.threshold,
                  "Still detector: a 1 s window whose gyro and accel variance over the quietest windows' (T, ~1 still) "
                  "exceeds this is motion")
      ->capture_default_str();
  sub->add_option("--still-rate", a->still_rate_hz, "Rows per second the still detector sees (means of the log's rows), Hz")
      ->capture_default_str();
  return {sub, [a, static_weight] {
            a->input = a->inputs.front();
            a->static_weight_given = static_weight->count() > 0;
            return Run(*a);
          }};
}

const CommandRegistrar kCalibrateRegistrar(kCalibrateName, 69, &MakeCalibrate);

}  // namespace
}  // namespace gyrocomp::cli
