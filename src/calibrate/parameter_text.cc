// The calibrate stage's text: the parameter file (its comment block and the PX4 / ArduPilot
// writers of param_export.h) and the per-sensor table of CalibrateResult::BriefReport.
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "calibrate_internal.h"
#include "gyrocomp/calibrate/calibrate.h"
#include "gyrocomp/core/format.h"
#include "gyrocomp/export/param_export.h"

namespace gyrocomp {
namespace calibrate_internal {

namespace {

ThreeAxisCubics Three(const Sensor& s) { return {s.cubics[0], s.cubics[1], s.cubics[2]}; }

const Sensor* Find(const std::vector<Sensor>& all, const std::string& type, int slot) {
  for (const Sensor& s : all)
    if (s.type == type && s.slot == slot && s.reason.empty()) return &s;
  return nullptr;
}

// "steady 1e-4 2e-4 3e-4" (firmware unit) or the reason no band is available.
std::string ExpectedTextOf(const Sensor& s, bool warm_up) {
  std::string t = warm_up ? "warm-up" : "steady";
  for (const auto& e : s.expected) {
    if (!e) return t + " n/a (" + s.band_reason + ")";
    if (warm_up && !e->warm_up) return t + " n/a (the run has no heating sample)";
    t += " " + FormatNumber((warm_up ? e->warm_up->total_rms : e->steady.total_rms) / s.to_model, 4);
  }
  return t;
}

// "static weight temperature time time (auto: expected error time 1e-4/..., temperature ...)".
std::string WeightTextOf(const Sensor& s) {
  std::string t = "static weight";
  for (const std::string& w : s.weights) t += " " + w;
  bool any = false;
  std::string time = "time", temp = "temperature";
  for (const auto& c : s.weight_choices) {
    if (!c) continue;
    time += (any ? "/" : " ") + FormatNumber(c->time.total_rms / s.to_model, 4);
    temp += (any ? "/" : " ") + FormatNumber(c->temperature.total_rms / s.to_model, 4);
    any = true;
  }
  if (any) t += " (auto, expected error " + time + ", " + temp + " " + s.unit + ")";
  if (!s.weight_reason.empty()) t += " (" + s.weight_reason + ")";
  return t;
}

std::string ValidationText(const Sensor::Validation& v) {
  if (!v.reason.empty()) return "validation: not scored, " + v.reason;
  std::string t = "validation run (" + std::to_string(v.rows) + " rows): RMS raw / cubic / full model";
  for (std::size_t k = 0; k < v.raw.size(); ++k) t += " " + FormatNumber(v.raw[k], 4) + "/" + FormatNumber(v.cubic[k], 4) + "/" + FormatNumber(v.full_model[k], 4);
  return t;
}

std::string Joined(const std::vector<std::string>& v) {
  std::string t;
  for (const std::string& x : v) t += (t.empty() ? "" : " + ") + x;
  return v.size() > 1 ? t + " (one cubic fitted to all their still rows, a constant per log or still segment)" : t;
}

// A pooled sensor's fit in words: the temperature it was fitted on (a lag kept or not) and, per
// axis, whether the shared dT/dt term was kept (pooled_fit.h; the fit's curve is at dT/dt = 0).
std::string PooledTermsTextOf(const Sensor& s) {
  std::string t = s.temp_lag_s > 0.0 ? "temperature lagged " + FormatNumber(s.temp_lag_s, 4) + " s (no dT/dt term)"
                                     : "logged temperature (no lag kept); dT/dt term";
  if (s.temp_lag_s > 0.0) return t;
  std::string kept;
  for (std::size_t k = 0; k < s.rate_gain.size() && k < s.cols.size(); ++k)
    if (s.rate_gain[k] != 0.0) kept += (kept.empty() ? "" : " ") + s.cols[k];
  return t + (kept.empty() ? " not kept" : " kept on " + kept);
}

// A pooled sensor's rows of the --verbose table (CalibrateResult::BriefReport), after its span:
// what the pooled fit has in place of a single run's projection cost, expected error and static
// weighting: the lag kept, each axis's dT/dt gain, the curve's 1 sigma, and what the exported cubic
// leaves against the fit's curve steady and at the heating state (the --optimise-for trade).
std::string PooledRowText(const Sensor& s, const std::string& optimise_for) {
  std::ostringstream t;
  auto per_axis = [&](const std::vector<double>& v) {
    for (double x : v) t << " " << FormatNumber(x, 3);
  };
  t << "pooled over " << s.runs_combined << " log(s), lag " << FormatNumber(s.temp_lag_s, 4) << " s, dT/dt gain";
  per_axis(s.rate_gain);
  t << " " << s.unit << " per C/s\n                  curve 1 sigma (pooled fit)";
  per_axis(s.curve_sd);
  t << " " << s.unit << "\n                  optimised for " << optimise_for << ": cubic - curve steady";
  per_axis(s.steady_rms);
  t << ", at the heating state";
  per_axis(s.warm_up_rms);
  t << " " << s.unit << (s.heating_state_kind.empty() ? " (no dT/dt term or lag kept: the steady curve)" : "") << "\n";
  return t.str();
}

// What --optimise-for did to a pooled sensor's cubic (CalibratedSensor::heating_state): "" for
// steady; otherwise the state the term was taken at, or that no term was kept (the steady curve).
std::string PooledConditionTextOf(const Sensor& s, const Args& a) {
  if (a.optimise_for == "steady") return "";
  const std::string head = "optimised for " + a.optimise_for + ": ";
  if (s.heating_state_kind.empty()) return head + "no dT/dt term or lag kept, the steady curve (the condition changes nothing)";
  double sum = 0.0, bins = 0.0;
  for (double v : s.heating_state.state)
    if (v != 0.0) sum += v, bins += 1.0;
  const bool lag = s.heating_state_kind == "lag_excess_c";
  return head + (lag ? "the lagged curve at T - (T - T_lag)" : "the curve + dT/dt gain x dT/dt") + ", the state the still rows had while heating (" +
         FormatNumber(bins > 0.0 ? sum / bins : 0.0, 3) + (lag ? " C" : " C/s") + " on average over " + FormatNumber(bins, 3) +
         " of " + std::to_string(s.heating_state.state.size()) + " 1 C bins, 0 in the others)" +
         (a.optimise_for == "both" ? ", averaged with the steady curve" : "");
}

// The header of a pooled fit (several logs, or one log not still throughout): what FitPooledCubic
// did and the condition the cubic was exported for; --static-weight has no part in it.
// The start of a sensor's header line, "  gyro 0 (device_id N)", into `l`; a skipped sensor's
// whole line (with its reason) goes into `c` instead and the answer is false.
bool SensorLineStart(const Sensor& s, std::ostringstream* l, std::vector<std::string>* c) {
  *l << "  " << s.type << " " << s.instance << (s.device_id ? " (device_id " + std::to_string(*s.device_id) + ")" : "");
  if (s.reason.empty()) return true;
  *l << ": SKIPPED, " << s.reason;
  c->push_back(l->str());
  return false;
}

std::vector<std::string> PooledComments(const Args& a) {
  return {
      "Thermal calibration generated by gyrocomp calibrate --format " + a.format + " from " + Joined(a.inputs),
      "(docs/explanation/flight-controller-export.md). Per sensor: one least-squares cubic in temperature over the",
      "still rows (block means at " + FormatNumber(a.fit_rate_hz, 4) + " Hz) of every log, with a constant per log (gyro, baro) or",
      "per still segment (accel), fitted on the logged temperature or on a lagged copy of it when the lag predicts",
      "held-out logs better; without a lag, a shared dT/dt term where the heating rates identify it and it earns",
      "its place, the fit's curve being the one at dT/dt = 0 (pooled_fit.h). Optimised for: " + a.optimise_for + " (steady:",
      "that curve; warm-up: the curve with the kept dT/dt gain or lag at the state the logs' still rows had while",
      "heating, by temperature, projected onto the cubic; both: their mean; no term kept: the steady curve).",
      "--static-weight does not apply (no drift model). Units: gyro rad/s, accel m/s^2, baro Pa; sensor frame.",
      "Per sensor and axis: the curve's 1 sigma from the fit (curve_sd, firmware unit), constant excluded."};
}

std::vector<std::string> Comments(const Args& a, const std::vector<Sensor>& all) {
  const bool pooled = std::any_of(all.begin(), all.end(), [](const Sensor& s) { return s.fit == "pooled"; });
  std::vector<std::string> c = pooled ? PooledComments(a) : std::vector<std::string>{
      "Thermal calibration generated by gyrocomp calibrate --format " + a.format + " from " + Joined(a.inputs),
      "(docs/explanation/flight-controller-export.md). Every sensor of the log: the library's default drift model (auto) fitted on",
      "block means at " + FormatNumber(a.fit_rate_hz, 4) + " Hz, its curve projected onto the firmware's cubic over the",
      "sensor's range, optimised for: " + a.optimise_for + " (steady: dT/dt = 0; warm-up: the state the run had while heating;",
      "both: their mean); static curve weighted by: " + a.static_weight + " (temperature: each temperature alike,",
      "the run's data with the model's dynamic part removed, 2000 bins; time: the model's own curve; auto: per",
      "axis the one with the lower expected next-run error of the estimator, docs/explanation/flight-controller-export.md).",
      "Units: gyro rad/s, accel m/s^2, baro Pa; sensor frame. Per sensor: model, projection cost",
      "(RMS full model - cubic on this run, firmware unit) and, per axis, the expected next-run error of the",
      "exported cubic: RMS of sqrt((cubic - model)^2 + sd^2), sd the model's prediction band / z (docs/explanation/flight-controller-export.md),",
      "at steady temperature and along this run's own heating (warm-up), constant excluded."};
  if (pooled) {
    for (const Sensor& s : all) {
      std::ostringstream l;
      if (!SensorLineStart(s, &l, &c)) continue;
      l << ": pooled over " << s.runs_combined << " log(s), " << FormatNumber(s.temp_min_c, 4) << ".."
        << FormatNumber(s.temp_max_c, 4) << " C, curve 1 sigma";
      for (double v : s.curve_sd) l << " " << FormatNumber(v, 4);
      c.push_back(l.str());
      c.push_back("    fitted on the " + PooledTermsTextOf(s));
      if (const std::string t = PooledConditionTextOf(s, a); !t.empty()) c.push_back("    " + t);
      if (s.validation) c.push_back("    " + ValidationText(*s.validation));
    }
    return c;
  }
  for (const Sensor& s : all) {
    std::ostringstream l;
    if (!SensorLineStart(s, &l, &c)) continue;
    l << ": " << (s.fit == "pooled" ? "pooled over " + std::to_string(s.runs_combined) + " log(s)" : DriftModelKindName(s.models[0].kind))
      << ", " << FormatNumber(s.temp_min_c, 4) << ".." << FormatNumber(s.temp_max_c, 4) << " C, cost";
    for (double v : s.cost_rms) l << " " << FormatNumber(v, 4);
    c.push_back(l.str());
    c.push_back("    expected error " + ExpectedTextOf(s, false) + "; " + ExpectedTextOf(s, true));
    c.push_back("    " + WeightTextOf(s));
    if (s.validation) c.push_back("    " + ValidationText(*s.validation));
  }
  return c;
}

}  // namespace

Result<std::string> ParameterText(const Args& a, const std::vector<Sensor>& all) {
  const auto comments = Comments(a, all);
  if (a.format == "px4") {
    Px4TcalFile f;
    for (const Sensor& s : all) {
      if (!s.reason.empty()) continue;
      if (!s.device_id) return InvalidInput(a.input + ": " + s.type + " " + std::to_string(s.instance) + " logs no device_id");
      if (s.type == "gyro") f.gyro.push_back({s.slot, *s.device_id, Three(s)});
      if (s.type == "accel") f.accel.push_back({s.slot, *s.device_id, Three(s)});
      if (s.type == "baro") f.baro.push_back({s.slot, *s.device_id, s.cubics[0]});
    }
    return WritePx4TcalFile(f, comments);
  }
  std::vector<ArduPilotTcalImu> imus;
  for (int n = 1; n <= 3; ++n) {
    ArduPilotTcalImu m;
    m.imu = n;
    const Sensor* g = Find(all, "gyro", n);
    const Sensor* acc = Find(all, "accel", n);
    if (g) m.gyro_radps = Three(*g);
    if (acc) m.accel_m_s2 = Three(*acc);
    if (!g && !acc) {
      m.disabled_reason = "IMU " + std::to_string(n - 1) + " not calibrated";
      for (const Sensor& s : all)
        if (s.slot == n && !s.reason.empty()) m.disabled_reason = s.type + ": " + s.reason;
      bool in_log = false;
      for (const Sensor& s : all) in_log |= s.slot == n;
      if (!in_log) m.disabled_reason = "IMU " + std::to_string(n - 1) + " not in the log";
    }
    imus.push_back(m);
  }
  return WriteArduPilotTcalFile(imus, comments);
}

}  // namespace calibrate_internal

std::string ExpectedErrorText(const CalibratedSensor& s, bool warm_up) { return calibrate_internal::ExpectedTextOf(s, warm_up); }
std::string StaticWeightText(const CalibratedSensor& s) { return calibrate_internal::WeightTextOf(s); }

std::string CalibrateResult::BriefReport() const {
  using namespace calibrate_internal;
  const std::vector<Sensor>& all = sensors;
  std::ostringstream t;
  t << "sensor  inst  slot  span_c         model          cost (RMS full - cubic, per axis)\n";
  for (const Sensor& s : all) {
    t << s.type << std::string(8 - std::min<std::size_t>(7, s.type.size()), ' ') << s.instance << "     " << s.slot << "     ";
    if (!s.reason.empty()) {
      t << "skipped: " << s.reason << "\n";
      continue;
    }
    std::string span = FormatNumber(s.temp_min_c, 4) + ".." + FormatNumber(s.temp_max_c, 4);
    if (s.fit == "pooled") {
      t << span << std::string(span.size() < 15 ? 15 - span.size() : 1, ' ') << PooledRowText(s, options.optimise_for);
      continue;
    }
    t << span << std::string(span.size() < 15 ? 15 - span.size() : 1, ' ') << DriftModelKindName(s.models[0].kind)
      << std::string(15 - std::min<std::size_t>(14, std::string(DriftModelKindName(s.models[0].kind)).size()), ' ');
    for (double v : s.cost_rms) t << FormatNumber(v, 4) << " ";
    t << s.unit << "\n";
    t << "                  expected next-run error of the cubic: " << ExpectedTextOf(s, false) << "; "
      << ExpectedTextOf(s, true) << " " << s.unit << "\n";
    t << "                  " << WeightTextOf(s) << "\n";
  }
  bool any_validation = false;
  for (const Sensor& s : all) any_validation |= s.validation.has_value();
  if (any_validation) {
    t << "validation run: RMS of block means, mean removed, per axis (raw / exported cubic, firmware formula / "
         "full model, causal)\n";
    for (const Sensor& s : all) {
      if (!s.validation) continue;
      t << s.type << std::string(8 - std::min<std::size_t>(7, s.type.size()), ' ') << s.instance << "     ";
      const Sensor::Validation& v = *s.validation;
      if (!v.reason.empty()) {
        t << "not scored: " << v.reason << "\n";
        continue;
      }
      for (std::size_t k = 0; k < v.raw.size(); ++k)
        t << s.cols[k] << " " << FormatNumber(v.raw[k], 4) << " / " << FormatNumber(v.cubic[k], 4) << " / " << FormatNumber(v.full_model[k], 4) << "   ";
      t << s.unit << "\n";
    }
  }
  t << "what the logs identify, per sensor (" << logs.size() << " log(s)):\n";
  for (const Sensor& s : all) {
    t << s.type << std::string(8 - std::min<std::size_t>(7, s.type.size()), ' ') << s.instance << "     " << s.fit << ": "
      << s.identification.statement << "\n";
    if (!s.identification.would_help.empty()) t << "                  would help: " << s.identification.would_help << "\n";
  }
  for (const LogStill& l : logs)
    t << "still in " << l.path << " (" << l.state << "): " << l.detection.BriefReport() << "\n";
  return t.str();
}

}  // namespace gyrocomp
