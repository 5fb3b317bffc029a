#include "result_json.h"

#include <cmath>

namespace gyrocomp::cli {

nlohmann::json Num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }
nlohmann::json Num(const std::optional<double>& v) { return v ? Num(*v) : nlohmann::json(); }

nlohmann::json AllanTermsJson(const AllanResult& r) {
  const AllanNoiseTerms& t = r.terms;
  nlohmann::json j;
  j["arw_deg_per_sqrt_h"] = Num(t.arw_deg_per_sqrt_h);
  j["arw_method"] = t.arw_method;
  j["arw_fit_deg_per_sqrt_h"] = Num(t.arw_fit_deg_per_sqrt_h);
  j["adev_min_deg_per_h"] = Num(t.adev_min_deg_per_h);
  j["tau_at_min_s"] = Num(t.tau_at_min_s);
  j["adev_min_at_longest_tau"] = t.min_at_longest_tau;
  j["adev_min_usable_deg_per_h"] = Num(t.adev_min_usable_deg_per_h);
  j["tau_at_min_usable_s"] = Num(t.tau_at_min_usable_s);
  j["adev_min_usable_at_longest_usable_tau"] = t.min_usable_at_longest_usable_tau;
  j["min_edf"] = Num(t.min_edf);
  j["num_taus_used"] = t.num_taus_used;
  j["rrw_fit_tau_range_s"] = {Num(t.rrw_fit_tau_min_s), Num(t.rrw_fit_tau_max_s)};
  j["bias_instability_deg_per_h"] = Num(t.bias_instability_deg_per_h);
  j["rrw_deg_per_h_per_sqrt_h"] = Num(t.rrw_deg_per_h_per_sqrt_h);
  // A figure that cannot be computed is null with "<key>_reason" beside it.
  if (!t.arw_deg_per_sqrt_h) {
    j["arw_deg_per_sqrt_h_reason"] = "tau = 1 s is beyond the longest tau of the curve (record too short)";
  }
  if (!t.arw_fit_deg_per_sqrt_h) {
    j["arw_fit_deg_per_sqrt_h_reason"] =
        "no usable tau before the minimum has a local slope near -1/2 (no white-rate region)";
  }
  if (!t.rrw_deg_per_h_per_sqrt_h) {
    j["rrw_deg_per_h_per_sqrt_h_reason"] =
        "no usable tau after the minimum has a local slope near +1/2 (no rate-random-walk region)";
  }
  if (!t.rrw_fit_tau_min_s) j["rrw_fit_tau_range_s_reason"] = "no +1/2 region was fitted";
  for (const char* key : {"adev_min_deg_per_h", "tau_at_min_s", "adev_min_usable_deg_per_h", "tau_at_min_usable_s",
                          "bias_instability_deg_per_h", "min_edf"}) {
    if (j[key].is_null()) j[std::string(key) + "_reason"] = "not a finite number (the curve holds a NaN or an infinity)";
  }
  j["conventions"] = {
      {"arw", "N = sigma(tau = 1 s) x sqrt(1 s), deg/sqrt(h) (IEEE 952; x 60 from deg/s*sqrt(s))"},
      {"adev_min", "minimum of the whole overlapping ADEV curve, deg/h (the paper's 'bias stability', as allantools users read it)"},
      {"adev_min_usable", "minimum of the overlapping ADEV over the taus with EDF >= min_edf, deg/h"},
      {"bias_instability", "B = adev_min / 0.664 (IEEE 952 flicker floor), deg/h"},
      {"rrw", "K = sigma(tau = 3 s) on the fitted +1/2 line, deg/h/sqrt(h) (IEEE 952)"}};
  return j;
}

nlohmann::json AllanJson(const AllanResult& r, bool with_curve) {
  nlohmann::json j = AllanTermsJson(r);
  j["fs_hz"] = r.fs_hz;
  j["n_samples"] = r.n_samples;
  if (with_curve) {
    const AllanCurve& c = r.curve;
    j["tau_s"] = c.tau_s;
    j["adev_dps"] = c.adev_dps;
    j["adev_error_dps"] = c.adev_error_dps;
    j["n_clusters"] = c.n_clusters;
    j["adev_lo_dps"] = c.adev_lo_dps;
    j["adev_hi_dps"] = c.adev_hi_dps;
    j["edf"] = c.edf;
    j["confidence"] = r.confidence;
  }
  j["deviation_method"] = r.deviation_method;
  j["edf_method"] = r.edf_method;
  return j;
}

nlohmann::json ModesJson(const std::vector<ModeReport>& modes) {
  nlohmann::json a = nlohmann::json::array();
  for (const ModeReport& m : modes) {
    a.push_back({{"index", m.index},
                 {"center_frequency_hz", Num(m.center_frequency_hz)},
                 {"center_frequency_cycles_per_sample", Num(m.center_frequency_cycles_per_sample)},
                 {"sample_entropy", Num(m.sample_entropy)},
                 {"class", FeatureClassName(m.feature)}});
  }
  return a;
}

nlohmann::json BandwidthJson(const BandwidthResult& b) {
  return {{"bandwidth_hz", Num(b.bandwidth_hz)},
          {"max_frequency_tested_hz", Num(b.max_frequency_hz)},
          {"delay_s", Num(b.delay_s)},
          {"dc_gain", Num(b.dc_gain)},
          {"frequency_hz", b.frequency_hz},
          {"gain", b.gain},
          {"method", "sine injection: gain of (process(b + A sin) - process(b)) at each test "
                     "frequency; bandwidth = lowest f with gain < 1/sqrt(2)"}};
}

nlohmann::json DriftSummaryJson(const DriftFitSummary& s) {
  nlohmann::json j;
  j["model"] = DriftModelKindName(s.model);
  j["inputs"] = DriftInputSetName(s.inputs);
  j["target"] = s.target_name;
  j["C"] = Num(s.C);
  j["gamma"] = Num(s.gamma);
  j["sigma"] = Num(s.sigma);
  j["epsilon"] = Num(s.epsilon);
  j["num_support"] = s.num_support;
  if (s.model == DriftModelKind::kPolynomial || s.model == DriftModelKind::kHybrid) {
    j["degree"] = s.degree;
    j["dtemp_degree"] = s.dtemp_degree;
    j["gain_temp_degree"] = s.gain_temp_degree;
  }
  j["lag_tau_s"] = Num(s.lag_tau_s);
  j["cv_scheme"] = DriftCvSchemeName(s.cv_scheme);
  j["cv_segments"] = s.cv_segments;
  nlohmann::json cands = nlohmann::json::array();
  for (const DriftCandidateScore& c : s.candidates)
    cands.push_back({{"name", c.name}, {"cv_rmse_dps", Num(c.cv_rmse)}, {"note", c.note}});
  j["candidates"] = cands;
  j["selection_reason"] = s.selection_reason;
  j["identifiability"] = s.identifiability;
  j["kernel_decision"] = s.kernel_decision;
  j["cv_folds"] = s.cv_folds;
  j["cv_rmse_dps"] = Num(s.cv_rmse);
  j["train_rmse_dps"] = Num(s.train_rmse);
  j["num_train"] = s.num_train;
  j["train_period_s"] = Num(s.train_period_s);
  j["temp_range_c"] = {Num(s.temp_min_c), Num(s.temp_max_c)};
  j["evaluations"] = s.evaluations;
  j["generations"] = s.generations;
  j["fit_time_s"] = Num(s.fit_time_s);
  return j;
}

nlohmann::json MethodRowJson(const MethodRow& m) {
  return {{"group", m.group},
          {"method", m.method},
          {"arw_deg_per_sqrt_h", Num(m.arw_deg_per_sqrt_h)},
          {"adev_min_deg_per_h", Num(m.adev_min_deg_per_h)},
          {"bias_instability_deg_per_h", Num(m.bias_instability_deg_per_h)},
          {"bandwidth_hz", Num(m.bandwidth_hz)},
          {"rmse_vs_true_rate_dps", Num(m.rmse_vs_true_rate_dps)},
          {"drift_rmse_vs_truth_dps", Num(m.drift_rmse_vs_truth_dps)},
          {"drift_cv_rmse_dps", Num(m.drift_cv_rmse_dps)},
          {"seconds", m.seconds},
          {"note", m.note}};
}

}  // namespace gyrocomp::cli

namespace gyrocomp::cli {

nlohmann::json DriftValidationJson(const DriftValidation& v) {
  nlohmann::json j;
  j["n_samples"] = v.num_samples;
  j["fs_hz"] = v.fs_hz;
  j["num_blocks"] = v.num_blocks;
  j["raw_drift_rms_dps"] = Num(v.raw_drift_rms);
  j["residual_drift_rms_dps"] = Num(v.residual_drift_rms);
  j["residual_mean_dps"] = Num(v.residual_mean);
  j["residual_slope_vs_temp_dps_per_c"] = Num(v.slope_vs_temp);
  j["residual_slope_vs_dtemp_dps_per_c_per_s"] = Num(v.slope_vs_dtemp);
  j["adev_tau_s"] = v.tau_s;
  j["adev_raw_dps"] = v.adev_raw;
  j["adev_compensated_dps"] = v.adev_compensated;
  j["rmse_vs_true_drift_dps"] = Num(v.rmse_vs_true_drift);
  j["fraction_temp_outside_fitted_range"] = v.fraction_temp_outside;
  j["fraction_dtemp_outside_fitted_range"] = v.fraction_dtemp_outside;
  j["temp_below_fitted_c"] = v.excursion.below_c;
  j["temp_above_fitted_c"] = v.excursion.above_c;
  // The prediction band on this run (null when the model file has none).
  j["band_level"] = Num(v.band_level);
  j["band_half_width_rms_dps"] = Num(v.band_half_width_rms);
  j["band_coverage_of_true_drift"] = Num(v.band_coverage_truth);
  j["band_coverage_of_block_means"] = Num(v.band_coverage_blocks);
  return j;
}

}  // namespace gyrocomp::cli
