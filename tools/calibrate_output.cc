// gyrocomp calibrate's outputs: the model files and the JSON
// (tools/calibrate_sensor.h; the fitting and the parameter text are the calibrate stage's).
#include <algorithm>
#include <filesystem>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "commands.h"
#include "calibrate_report.h"
#include "gyrocomp/core/format.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/cubic_score.h"
#include "gyrocomp/export/param_export.h"
#include "gyrocomp/export/static_weight.h"
#include "gyrocomp/export/thermal_cubic.h"
#include "result_json.h"
#include "calibrate_sensor.h"

namespace gyrocomp::cli::calibrate {

namespace {

nlohmann::json ConditionJson(const CubicConditionError& e, double to_model) {
  return {{"total_rms", e.total_rms / to_model}, {"projection_rms", e.projection_rms / to_model},
          {"band_sd_rms", e.band_sd_rms / to_model}, {"samples", e.num_samples}};
}

// Per axis, firmware unit: the exported cubic's expected next-run error in each condition.
nlohmann::json ExpectedJson(const CalibrateArgs& a, const Sensor& s) {
  nlohmann::json steady = nlohmann::json::array(), warm = nlohmann::json::array(), axes = nlohmann::json::array();
  nlohmann::json proj_steady = nlohmann::json::array(), proj_warm = nlohmann::json::array();
  nlohmann::json level = nullptr;
  for (std::size_t k = 0; k < s.models.size(); ++k) {
    proj_steady.push_back(s.steady_rms[k]);
    proj_warm.push_back(s.warm_up_rms[k]);
    const auto& e = s.expected[k];
    if (e) level = e->level;
    steady.push_back(e ? nlohmann::json(e->steady.total_rms / s.to_model) : nlohmann::json(nullptr));
    warm.push_back(e && e->warm_up ? nlohmann::json(e->warm_up->total_rms / s.to_model) : nlohmann::json(nullptr));
    nlohmann::json ax = {{"col", s.cols[k]}};
    if (e) {
      ax["steady"] = ConditionJson(e->steady, s.to_model);
      ax["warm_up"] = e->warm_up ? ConditionJson(*e->warm_up, s.to_model) : nlohmann::json(nullptr);
    }
    axes.push_back(ax);
  }
  nlohmann::json j = {{"optimised_for", a.optimise_for}, {"band_level", level}, {"steady", steady}, {"warm_up", warm},
                      {"projection_steady", proj_steady}, {"projection_warm_up", proj_warm}, {"axes", axes}};
  if (!s.band_reason.empty()) j["steady_reason"] = j["warm_up_reason"] = s.band_reason;
  j["note"] = "per axis, firmware unit: expected next-run RMS error of the exported cubic, RMS of sqrt((cubic - "
              "model)^2 + sd^2) with sd the model's prediction band / z(band_level), at steady temperature (a "
              "slow ramp over the range) and along this run's heating samples (warm_up); projection_*: the "
              "cubic - model part alone, over the range";
  return j;
}

nlohmann::json EstimatorJson(const StaticEstimatorError& e, double to_model) {
  return {{"total_rms", e.total_rms / to_model}, {"rate_gain_rms", e.rate_gain_rms / to_model},
          {"noise_rms", e.noise_rms / to_model}};
}

// --static-weight auto's comparison for axis k (firmware unit), or null with the reason.
nlohmann::json WeightChoiceJson(const Sensor& s, std::size_t k) {
  const auto& c = s.weight_choices[k];
  if (!c) return s.weight_reason.empty() ? nlohmann::json(nullptr) : nlohmann::json({{"reason", s.weight_reason}});
  return {{"chosen", StaticWeightName(c->chosen)}, {"time", EstimatorJson(c->time, s.to_model)},
          {"temperature", EstimatorJson(c->temperature, s.to_model)},
          {"unidentified_rate_gain_rms", c->rate_gain_rms / s.to_model}, {"reason", c->reason},
          {"note", "expected next-run RMS error of each estimator of the static cubic (constant removed): the left-out "
                   "dT/dt gain G (Eq. B-4) times what the estimator makes of the run's dT/dt, and the run's noise "
                   "(the band's Eq. G-0) through the estimator; over the --optimise-for conditions"}};
}

nlohmann::json ValidationJson(const Sensor::Validation& v) {
  if (!v.reason.empty()) return {{"status", "not scored"}, {"reason", v.reason}};
  return {{"status", "scored"}, {"rows", v.rows}, {"temp_min_c", v.temp_min_c}, {"temp_max_c", v.temp_max_c},
          {"raw_rms", v.raw}, {"cubic_rms", v.cubic}, {"full_model_rms", v.full_model}};
}

}  // namespace

nlohmann::json SensorJson(const CalibrateArgs& a, const Sensor& s) {
  nlohmann::json j = {{"type", s.type}, {"instance", s.instance}, {"slot", s.slot},
                      {"status", s.reason.empty() ? "calibrated" : "skipped"}};
  if (a.format == "px4") j["device_id"] = s.device_id ? nlohmann::json(*s.device_id) : nlohmann::json(nullptr);
  else j["imu"] = s.slot;
  const CalibratedSensor::Identification& id = s.identification;
  j["identification"] = {{"statement", id.statement}, {"would_help", id.would_help}, {"temp_min_c", id.temp_min_c},
                         {"temp_max_c", id.temp_max_c}, {"identified_span_c", id.identified_span_c},
                         {"overlap_c", id.overlap_c}, {"logs", id.logs}, {"logs_with_still", id.logs_with_still},
                         {"still_s", id.still_s}};
  j["fit"] = s.fit;
  if (!s.reason.empty()) {
    j["reason"] = s.reason;
    return j;
  }
  if (!s.curve_sd.empty()) j["curve_sd"] = s.curve_sd;
  if (s.fit == "pooled") {
    // The lag search (CalibratedSensor::temp_lag_s, lag_term; Eq. A-4) and each axis's dT/dt gain.
    auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
    j["temp_lag_s"] = s.temp_lag_s;
    j["lag_term"] = {{"gain", s.lag_term.pairs ? finite(s.lag_term.gain) : nlohmann::json()},
                     {"gain_se", s.lag_term.pairs ? finite(s.lag_term.se) : nlohmann::json()},
                     {"groups", s.lag_term.pairs}, {"admitted", s.lag_term.Admitted()}};
    j["rate_gain"] = s.rate_gain;
    // The state --optimise-for warm-up / both take the kept term at (CalibratedSensor::heating_state).
    j["heating_state"] = s.heating_state_kind.empty()
                             ? nlohmann::json(nullptr)
                             : nlohmann::json{{"kind", s.heating_state_kind}, {"t0_c", s.heating_state.t0_c},
                                              {"bin_c", s.heating_state.bin_c}, {"state", s.heating_state.state}};
  }
  j["temp_min_c"] = s.temp_min_c;
  j["temp_max_c"] = s.temp_max_c;
  j["runs_combined"] = s.runs_combined;
  j["kind"] = DriftModelKindName(s.models[0].kind);
  j["unit"] = s.unit;
  nlohmann::json axes = nlohmann::json::array();
  for (std::size_t k = 0; k < s.models.size(); ++k) {
    const TemperatureCubic& c = s.cubics[k];
    axes.push_back({{"col", s.cols[k]}, {"kind", DriftModelKindName(s.models[k].kind)},
                    {"cubic", {{"ref_temp_c", c.ref_temp_c}, {"temp_min_c", c.temp_min_c}, {"temp_max_c", c.temp_max_c},
                               {"coeff", c.coeff}}},
                    {"projection_cost_rms", s.cost_rms[k]}, {"fit_rmse", s.models[k].summary.train_rmse / s.to_model},
                    {"static_weight", s.weights[k]}, {"static_weight_choice", WeightChoiceJson(s, k)}});
  }
  j["axes"] = axes;
  j["expected_error"] = ExpectedJson(a, s);
  if (s.validation) j["validation"] = ValidationJson(*s.validation);
  return j;
}

Status WriteModels(const CalibrateArgs& a, const std::vector<Sensor>& all) {
  if (a.models_dir.empty()) return Status::Ok();
  std::error_code ec;
  std::filesystem::create_directories(a.models_dir, ec);
  if (ec) return IoError(a.models_dir + ": cannot create the directory: " + ec.message());
  for (const Sensor& s : all) {
    if (!s.reason.empty()) continue;
    DriftModelSet set;
    set.axes = s.models;
    set.device_id = s.device_id;
    set.sensor = SensorIdentity{s.type, s.instance, s.device_id, "sensor"};
    const std::string path = (std::filesystem::path(a.models_dir) / (s.type + std::to_string(s.instance) + ".json")).string();
    if (Status st = SaveDriftModelSet(set, path); !st.ok()) return st;
  }
  return Status::Ok();
}

}  // namespace gyrocomp::cli::calibrate
