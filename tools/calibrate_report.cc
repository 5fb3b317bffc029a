#include "calibrate_report.h"

#include <algorithm>
#include <cstdio>
#include <limits>

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

// The gyro cubics on one temperature grid over the union of their ranges.
nlohmann::json CurveChart(const std::vector<CalibrateCurve>& curves) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& c : curves) lo = std::min(lo, c.cubic.temp_min_c), hi = std::max(hi, c.cubic.temp_max_c);
  constexpr int kPoints = 201;
  std::vector<double> x(kPoints);
  for (int i = 0; i < kPoints; ++i) x[i] = lo + (hi - lo) * i / (kPoints - 1);
  nlohmann::json series = nlohmann::json::array();
  for (const auto& c : curves) {
    std::vector<double> y(kPoints);
    for (int i = 0; i < kPoints; ++i) y[i] = c.cubic.Evaluate(x[i]) * c.to_display;
    series.push_back({{"name", c.name}, {"y", y}, {"axis", "rate"}});
  }
  return {{"title", "Exported gyro cubics against temperature"},
          {"note", "The correction each gyro axis's parameters make at each temperature (deg/s), clamped outside the "
                   "calibrated range as the firmware clamps T."},
          {"x_label", "temperature (deg C)"}, {"x", x}, {"series", series}};
}

}  // namespace

ReportData BuildCalibrateReport(const nlohmann::json& summary, const std::vector<CalibrateCurve>& gyro_curves) {
  ReportData data;
  nlohmann::json& c = data.content;
  c["title"] = "Thermal calibration: " + summary["format"].get<std::string>() + " parameters";
  c["subtitle"] = summary["input"].get<std::string>() + " -> " + summary["output"].get<std::string>();
  c["summary"] = SensorsTable(summary);
  c["tables"] = nlohmann::json::array({CoefficientTable(summary)});  // array(): "= {x}" of one json is x itself under clang
  if (!summary["validation_run"].is_null()) c["tables"].push_back(ValidationTable(summary));
  if (!gyro_curves.empty()) c["timeseries"] = CurveChart(gyro_curves);
  nlohmann::json parameters = summary;
  parameters.erase("sensors");
  c["parameters"] = parameters;
  c["versions"] = SoftwareVersions();
  return data;
}

}  // namespace gyrocomp::cli
