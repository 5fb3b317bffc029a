#include "calibrate_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "gyrocomp/core/format.h"
#include "report_builder.h"

namespace gyrocomp::cli {
namespace {

std::string Fmt(const nlohmann::json& v) {
  if (v.is_null()) return "n/a";
  if (!v.is_number()) return v.is_string() ? v.get<std::string>() : v.dump();
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v.get<double>());
  return buf;
}

// "a / b / c" of a per-axis array.
std::string PerAxis(const nlohmann::json& a) {
  if (!a.is_array()) return Fmt(a);
  std::string t;
  for (const auto& v : a) t += (t.empty() ? "" : " / ") + Fmt(v);
  return t;
}

nlohmann::json SensorsTable(const nlohmann::json& summary) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& s : summary["sensors"]) {
    const std::string name = s["type"].get<std::string>() + " " + std::to_string(s["instance"].get<int>());
    if (s["status"] != "calibrated") {
      rows.push_back({name, s["slot"], "skipped", s.value("reason", ""), "", "", "", ""});
      continue;
    }
    nlohmann::json cost = nlohmann::json::array();
    for (const auto& ax : s["axes"]) cost.push_back(ax["projection_cost_rms"]);
    const auto& e = s["expected_error"];
    rows.push_back({name, s["slot"], "calibrated", Fmt(s["temp_min_c"]) + " .. " + Fmt(s["temp_max_c"]), s["kind"],
                    PerAxis(cost), PerAxis(e["steady"]), PerAxis(e["warm_up"]) + " " + s["unit"].get<std::string>()});
  }
  return {{"title", "Sensors"},
          {"columns", {"sensor", "slot", "status", "span (deg C) / reason", "model", "projection cost (RMS full - cubic)",
                       "expected error, steady", "expected error, warm-up"}},
          {"rows", rows},
          {"note", "Per axis (x / y / z), firmware unit (gyro rad/s, accel m/s^2, baro Pa). Expected error: the "
                   "exported cubic's expected next-run RMS, RMS of sqrt((cubic - model)^2 + sd^2), sd the model's "
                   "prediction band / z, at steady temperature and along the calibration run's heating (docs/explanation/flight-controller-export.md). "
                   "Optimised for: " + summary["optimised_for"].get<std::string>() + "."}};
}

nlohmann::json CoefficientTable(const nlohmann::json& summary) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& s : summary["sensors"]) {
    if (s["status"] != "calibrated") continue;
    for (const auto& ax : s["axes"]) {
      const auto& c = ax["cubic"];
      rows.push_back({s["type"].get<std::string>() + " " + std::to_string(s["instance"].get<int>()), ax["col"],
                      Fmt(c["ref_temp_c"]), Fmt(c["temp_min_c"]) + " .. " + Fmt(c["temp_max_c"]), Fmt(c["coeff"][0]),
                      Fmt(c["coeff"][1]), Fmt(c["coeff"][2]), Fmt(c["coeff"][3])});
    }
  }
  return {{"title", "Exported cubics"},
          {"columns", {"sensor", "axis", "ref (deg C)", "range (deg C)", "c0", "c1", "c2", "c3"}},
          {"rows", rows},
          {"note", "offset(T) = c0 + c1 dT + c2 dT^2 + c3 dT^3, dT = clamp(T) - ref, firmware unit, sensor frame; the "
                   "constant removed as the file needs (docs/explanation/flight-controller-export.md). The parameter file holds them as float32."}};
}

nlohmann::json ValidationTable(const nlohmann::json& summary) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& s : summary["sensors"]) {
    if (!s.contains("validation")) continue;
    const auto& v = s["validation"];
    const std::string name = s["type"].get<std::string>() + " " + std::to_string(s["instance"].get<int>());
    if (v["status"] != "scored") {
      rows.push_back({name, "not scored: " + v["reason"].get<std::string>(), "", "", ""});
      continue;
    }
    rows.push_back({name, Fmt(v["temp_min_c"]) + " .. " + Fmt(v["temp_max_c"]), PerAxis(v["raw_rms"]),
                    PerAxis(v["cubic_rms"]), PerAxis(v["full_model_rms"]) + " " + s["unit"].get<std::string>()});
  }
  return {{"title", "Validation on " + summary["validation_run"].get<std::string>()},
          {"columns", {"sensor", "span (deg C)", "raw", "exported cubic (firmware formula)", "full model (causal)"}},
          {"rows", rows},
          {"note", "Per axis, firmware unit: RMS of the " + Fmt(summary["block_s"]) +
                   " s block means of value - correction, their mean removed (the constant is the boot offset "
                   "calibration's). Cubic: the firmware's formula in float32, T clamped (ArduPilot: CALTEMP = the run's "
                   "first temperature); full model: apply --causal, the generated C."}};
}

// ---- one section per sensor -------------------------------------------------------------------

using FitRows = CalibratedSensor::FitRows;

std::string SensorName(const CalibratedSensor& s) { return s.type + " " + std::to_string(s.instance); }

// v minus the mean of its row's group (FitRows::group): the constant each log (or still segment)
// carries, removed as the pooled fit removes it (calibrate.h; where the pooled fit keeps a dT/dt
// term, its own constants differ from these by the term's mean over the group).
std::vector<double> MinusGroupMean(const std::vector<double>& v, const std::vector<int>& group) {
  std::map<int, std::pair<double, double>> sum;  // group -> (sum, rows)
  for (std::size_t i = 0; i < v.size(); ++i) sum[group[i]].first += v[i], sum[group[i]].second += 1.0;
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[i] = v[i] - sum[group[i]].first / sum[group[i]].second;
  return out;
}

double RowsRms(const std::vector<double>& v) {
  double ss = 0.0;
  for (double x : v) ss += x * x;
  return v.empty() ? NAN : std::sqrt(ss / static_cast<double>(v.size()));
}

// One axis of the rows the fit saw, display unit: the drift with each group's constant about the
// exported cubic removed, the residual after the cubic, and the uncompensated drift (each
// group's mean removed: what the boot offset calibration alone leaves).
struct AxisRows {
  std::vector<double> drift, residual, uncompensated;
};

AxisRows AxisOf(const FitRows& r, std::size_t k, const TemperatureCubic& c, double to_display) {
  std::vector<double> minus_cubic(r.temp_c.size());
  for (std::size_t i = 0; i < r.temp_c.size(); ++i) minus_cubic[i] = r.values[k][i] - c.Evaluate(r.temp_c[i]);
  AxisRows a;
  a.residual = MinusGroupMean(minus_cubic, r.group);
  a.uncompensated = MinusGroupMean(r.values[k], r.group);
  for (std::size_t i = 0; i < r.temp_c.size(); ++i) {
    a.drift.push_back((a.residual[i] + c.Evaluate(r.temp_c[i])) * to_display);
    a.residual[i] *= to_display, a.uncompensated[i] *= to_display;
  }
  return a;
}

// Points drawn per log and chart at most: every k-th row beyond (a subset keeps the rows' scatter,
// which means of rows would shrink); the tables use every row.
constexpr std::size_t kMaxPointsPerLog = 2500;

// The points of `y` against temperature, one series per log (report.h, sections: points), with
// the log's rows and the stride drawn ("rows", "every").
nlohmann::json PointsPerLog(const FitRows& r, const std::vector<double>& y, const std::vector<std::string>& logs) {
  std::map<int, std::vector<std::size_t>> rows_of_log;
  for (std::size_t i = 0; i < y.size(); ++i) rows_of_log[r.log[i]].push_back(i);
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [log, rows] : rows_of_log) {
    const std::size_t every = (rows.size() + kMaxPointsPerLog - 1) / kMaxPointsPerLog;
    std::vector<double> xs, ys;
    for (std::size_t j = 0; j < rows.size(); j += every) xs.push_back(r.temp_c[rows[j]]), ys.push_back(y[rows[j]]);
    const auto l = static_cast<std::size_t>(log);
    out.push_back({{"name", l < logs.size() ? logs[l] : "log " + std::to_string(log + 1)}, {"x", xs}, {"y", ys},
                   {"rows", rows.size()}, {"every", every}});
  }
  return out;
}

// The temperatures the curve is drawn at: the band's, or 201 over the cubic's range.
std::vector<double> CurveGrid(const CalibratedSensor::CurveBand& b, const TemperatureCubic& c) {
  if (!b.temp_c.empty()) return b.temp_c;
  std::vector<double> x;
  for (int i = 0; i <= 200; ++i) x.push_back(c.temp_min_c + (c.temp_max_c - c.temp_min_c) * i / 200.0);
  return x;
}

// The band center(T) -/+ z sd(T), display unit (report.h, sections: bands); null without a band.
nlohmann::json BandJson(const CalibratedSensor::CurveBand& b, const std::vector<double>& center, double to_display) {
  if (b.sd.empty()) return nullptr;
  std::vector<double> lo, hi;
  for (std::size_t i = 0; i < b.sd.size(); ++i) {
    lo.push_back(center[i] - b.z * b.sd[i] * to_display);
    hi.push_back(center[i] + b.z * b.sd[i] * to_display);
  }
  return {{"name", std::to_string(static_cast<int>(std::lround(100 * b.level))) + "% band"}, {"x", b.temp_c}, {"lo", lo}, {"hi", hi}};
}

std::string BandWidthNote(const CalibratedSensor& s) {
  if (s.fit == "pooled")
    return "Band: +-z sd with sd the pooled fit's 1 sigma of the curve (curve_sd, its RMS over the range, so the same width "
           "at every temperature).";
  return "Band: +-z sd(T), sd(T) = sqrt((cubic - model)^2 + band sd^2) at steady temperature: the exported cubic's expected "
         "next-run error at each temperature (its RMS over the range is the expected error, steady).";
}

std::string BandNote(const CalibratedSensor& s) {
  const std::string noise = " The band is about the drift: the rows also hold their own noise (means over 1 / --fit-rate), "
                            "so judge the residual's trend against it, not single points.";
  return BandWidthNote(s) + noise;
}

// (a) the drift the fit saw with the exported curve and its band; (b) the residual after it.
nlohmann::json DriftChart(const CalibratedSensor& s, std::size_t k, const AxisRows& a, const std::vector<std::string>& logs) {
  const TemperatureCubic& c = s.cubics[k];
  const CalibratedSensor::CurveBand& b = s.curve_bands[k];
  const std::vector<double> x = CurveGrid(b, c);
  std::vector<double> y;
  for (double t : x) y.push_back(c.Evaluate(t) * s.to_model);
  nlohmann::json chart = {{"title", s.cols[k] + ": drift and exported cubic"}, {"x_label", "temperature (deg C)"},
                          {"y_label", s.cols[k] + " (" + s.model_unit + ")"},
                          {"points", PointsPerLog(s.fit_rows, a.drift, logs)},
                          {"lines", {{{"name", "exported cubic"}, {"x", x}, {"y", y}}}}, {"bands", nlohmann::json::array()}};
  if (nlohmann::json band = BandJson(b, y, s.to_model); !band.is_null()) chart["bands"].push_back(band);
  return chart;
}

nlohmann::json ResidualChart(const CalibratedSensor& s, std::size_t k, const AxisRows& a, const std::vector<std::string>& logs) {
  const CalibratedSensor::CurveBand& b = s.curve_bands[k];
  const std::vector<double> zero(b.temp_c.size(), 0.0);
  nlohmann::json chart = {{"title", s.cols[k] + ": residual after the cubic"}, {"x_label", "temperature (deg C)"},
                          {"y_label", "residual (" + s.model_unit + ")"},
                          {"points", PointsPerLog(s.fit_rows, a.residual, logs)},
                          {"lines", nlohmann::json::array()}, {"bands", nlohmann::json::array()}};
  if (nlohmann::json band = BandJson(b, zero, s.to_model); !band.is_null()) chart["bands"].push_back(band);
  return chart;
}

std::string ErrorTableNote(const CalibratedSensor& s) {
  const bool pooled = s.fit == "pooled";
  return "On the " + std::to_string(s.fit_rows.temp_c.size()) + " rows the fit saw (" +
         (pooled ? "every log's still rows" : "the run's block means") +
         "), " + s.model_unit + ": uncompensated = each log's constant removed (the boot offset calibration alone), "
         "compensated = the residual after the exported cubic. " +
         (pooled ? "Curve 1 sigma: the pooled fit's uncertainty of the curve (curve_sd), not the noise of a next run; "
                   "no warm-up figure."
                 : "Expected next-run error: the RMS of the band's sd (the Sensors table's steady figure) and the Sensors "
                   "table's warm-up figure, here in " + s.model_unit + ".");
}

// (c) per axis: RMS before (offset only) and after the cubic on the fit's rows, beside the
// expected next-run error (the band's RMS sd, steady; the JSON's warm-up figure).
nlohmann::json ErrorTable(const CalibratedSensor& s, const nlohmann::json& sj, const std::vector<AxisRows>& axes) {
  nlohmann::json rows = nlohmann::json::array();
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const double before = RowsRms(axes[k].uncompensated), after = RowsRms(axes[k].residual);
    const std::vector<double>& sd = s.curve_bands[k].sd;
    const nlohmann::json steady = sd.empty() ? nlohmann::json(nullptr) : nlohmann::json(RowsRms(sd) * s.to_model);
    const nlohmann::json& w = sj["expected_error"]["warm_up"][k];
    const nlohmann::json warm = w.is_number() ? nlohmann::json(w.get<double>() * s.to_model) : nlohmann::json(nullptr);
    rows.push_back({s.cols[k], before, after, before > 0 ? nlohmann::json(after / before) : nlohmann::json(nullptr), steady, warm});
  }
  return {{"columns", {"axis", "uncompensated RMS", "compensated RMS", "after / before",
                       s.fit == "pooled" ? "curve 1 sigma (RMS over the range)" : "expected next-run error, steady",
                       "expected, warm-up"}},
          {"rows", rows}, {"note", ErrorTableNote(s)}};
}

std::string SectionNote(const CalibratedSensor& s) {
  return "Left: the rows the fit saw (" + std::to_string(s.fit_rows.temp_c.size()) + " rows, " + FormatNumber(s.temp_min_c, 4) +
         " .. " + FormatNumber(s.temp_max_c, 4) + " C), coloured per log, each log's constant (an accelerometer's: each "
         "still segment's) removed about the exported cubic, as the pooled fit removes it; line: the exported cubic, " +
         s.model_unit + ". Right: the residual, those rows minus the curve. " + BandNote(s) + " Beyond " +
         std::to_string(kMaxPointsPerLog) + " rows per log every k-th is drawn; the table uses all. " +
         s.identification.statement + ".";
}

nlohmann::json SkippedSection(const CalibratedSensor& s) {
  std::string note = "Not calibrated: " + s.reason + ".";
  if (!s.identification.would_help.empty()) note += " Would help: " + s.identification.would_help + ".";
  return {{"title", SensorName(s) + ": skipped"}, {"note", note}, {"charts", nlohmann::json::array()}};
}

nlohmann::json SensorSection(const CalibratedSensor& s, const nlohmann::json& sj, const std::vector<std::string>& logs) {
  if (!s.calibrated()) return SkippedSection(s);
  std::vector<AxisRows> axes;
  nlohmann::json charts = nlohmann::json::array();
  for (std::size_t k = 0; k < s.cubics.size(); ++k) {
    axes.push_back(AxisOf(s.fit_rows, k, s.cubics[k], s.to_model));
    charts.push_back(DriftChart(s, k, axes.back(), logs));
    charts.push_back(ResidualChart(s, k, axes.back(), logs));
  }
  const std::string fit = s.fit == "pooled" ? "pooled cubic over " + std::to_string(s.runs_combined) + " log(s)"
                                            : "single run, " + sj["kind"].get<std::string>() + " model projected onto the cubic";
  return {{"title", SensorName(s) + " (slot " + std::to_string(s.slot) + "): " + fit},
          {"note", SectionNote(s)},
          {"table", ErrorTable(s, sj, axes)}, {"charts", charts}};
}

std::vector<std::string> LogNames(const nlohmann::json& summary) {
  std::vector<std::string> names;
  for (const auto& p : summary["inputs"]) names.push_back(std::filesystem::path(p.get<std::string>()).filename().string());
  return names;
}

}  // namespace

ReportData BuildCalibrateReport(const nlohmann::json& summary, const std::vector<CalibratedSensor>& sensors) {
  ReportData data;
  nlohmann::json& c = data.content;
  c["title"] = "Thermal calibration: " + summary["format"].get<std::string>() + " parameters";
  c["subtitle"] = summary["input"].get<std::string>() + " -> " + summary["output"].get<std::string>();
  c["summary"] = SensorsTable(summary);
  c["tables"] = nlohmann::json::array({CoefficientTable(summary)});  // array(): "= {x}" of one json is x itself under clang
  if (!summary["validation_run"].is_null()) c["tables"].push_back(ValidationTable(summary));
  c["sections"] = nlohmann::json::array();
  const std::vector<std::string> logs = LogNames(summary);
  for (std::size_t i = 0; i < sensors.size() && i < summary["sensors"].size(); ++i)
    c["sections"].push_back(SensorSection(sensors[i], summary["sensors"][i], logs));
  nlohmann::json parameters = summary;
  parameters.erase("sensors");
  c["parameters"] = parameters;
  c["versions"] = SoftwareVersions();
  return data;
}

}  // namespace gyrocomp::cli
