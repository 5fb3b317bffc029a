// Drift model: options, features, decimation, fitting and prediction (see drift_model.h).
#include "gyrocomp/drift/drift_model.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "drift_model_internal.h"
#include "gyrocomp/core/format.h"

namespace gyrocomp {
namespace {

bool ValidDimension(const SearchDimension& d, const std::string& field, std::string* error) {
  if (!std::isfinite(d.lower) || !std::isfinite(d.upper) || !(d.lower > 0.0) || !(d.lower < d.upper)) {
    if (error)
      *error = "SvrSearchOptions::" + field + " = [" + FormatNumber(d.lower) + ", " + FormatNumber(d.upper) +
               "]: must satisfy 0 < lower < upper";
    return false;
  }
  return true;
}

}  // namespace

std::optional<DriftModelKind> ParseDriftModelKind(std::string_view name) {
  if (name == "poly") return DriftModelKind::kPolynomial;
  if (name == "svr") return DriftModelKind::kSvr;
  if (name == "grid-svr") return DriftModelKind::kGridSvr;
  if (name == "cs-svr") return DriftModelKind::kCsSvr;
  if (name == "hybrid") return DriftModelKind::kHybrid;
  if (name == "auto") return DriftModelKind::kAuto;
  return std::nullopt;
}

const char* DriftModelKindName(DriftModelKind kind) {
  switch (kind) {
    case DriftModelKind::kPolynomial: return "poly";
    case DriftModelKind::kSvr: return "svr";
    case DriftModelKind::kGridSvr: return "grid-svr";
    case DriftModelKind::kCsSvr: return "cs-svr";
    case DriftModelKind::kHybrid: return "hybrid";
    case DriftModelKind::kAuto: return "auto";
  }
  return "?";
}

std::optional<OutOfRangePolicy> ParseOutOfRangePolicy(std::string_view name) {
  if (name == "extrapolate") return OutOfRangePolicy::kExtrapolate;
  if (name == "clamp") return OutOfRangePolicy::kClamp;
  return std::nullopt;
}

const char* OutOfRangePolicyName(OutOfRangePolicy policy) {
  return policy == OutOfRangePolicy::kClamp ? "clamp" : "extrapolate";
}

std::optional<DriftCvScheme> ParseDriftCvScheme(std::string_view name) {
  if (name == "blocks") return DriftCvScheme::kBlocks;
  if (name == "segments") return DriftCvScheme::kThermalSegments;
  return std::nullopt;
}

const char* DriftCvSchemeName(DriftCvScheme scheme) {
  return scheme == DriftCvScheme::kThermalSegments ? "segments" : "blocks";
}

bool DriftAutoOptions::IsValid(std::string* error) const {
  if (search_generations < 1) {
    if (error) *error = "DriftAutoOptions::search_generations = " + std::to_string(search_generations) + ": must be >= 1";
    return false;
  }
  if (!(lag_tau_min_s > 0.0) || !(lag_tau_min_s < lag_tau_max_s) || !std::isfinite(lag_tau_max_s)) {
    if (error)
      *error = "DriftAutoOptions::lag_tau_min_s/lag_tau_max_s = " + FormatNumber(lag_tau_min_s) + "/" + FormatNumber(lag_tau_max_s) +
               ": must satisfy 0 < min < max";
    return false;
  }
  if (lag_tau_evaluations < 3) {
    if (error)
      *error = "DriftAutoOptions::lag_tau_evaluations = " + std::to_string(lag_tau_evaluations) + ": must be >= 3";
    return false;
  }
  if (lagged_curve_gain_degree < 0 || lagged_curve_gain_degree > 2) {
    if (error)
      *error = "DriftAutoOptions::lagged_curve_gain_degree = " + std::to_string(lagged_curve_gain_degree) +
               ": must be in 0..2";
    return false;
  }
  if (lagged_curve_pieces < 1) {
    if (error)
      *error = "DriftAutoOptions::lagged_curve_pieces = " + std::to_string(lagged_curve_pieces) + ": must be >= 1";
    return false;
  }
  return true;
}

bool PolynomialOptions::IsValid(std::string* error) const {
  if (degree < 1 || degree > 5) {
    if (error) *error = "PolynomialOptions::degree = " + std::to_string(degree) + ": must be in 1..5";
    return false;
  }
  if (dtemp_degree < 1 || dtemp_degree > 3) {
    if (error)
      *error = "PolynomialOptions::dtemp_degree = " + std::to_string(dtemp_degree) + ": must be in 1..3";
    return false;
  }
  if (gain_temp_degree < 0 || gain_temp_degree > 2) {
    if (error)
      *error = "PolynomialOptions::gain_temp_degree = " + std::to_string(gain_temp_degree) + ": must be in 0..2";
    return false;
  }
  return true;
}

bool SvrSearchOptions::IsValid(std::string* error) const {
  if (!ValidDimension(C, "C", error) || !ValidDimension(sigma, "sigma", error)) return false;
  if (epsilon && !ValidDimension(*epsilon, "epsilon", error)) return false;
  // The searched values must be valid SvrOptions (a fit must give a loadable model).
  auto within = [&](const SearchDimension& d, double lo, double hi, const char* range) {
    if (d.lower >= lo && d.upper <= hi) return true;
    if (error) *error = "SvrSearchOptions::" + d.name + " = [" + FormatNumber(d.lower) + ", " + FormatNumber(d.upper) +
                        "]: must lie in " + range;
    return false;
  };
  if (!within(C, 0.0, SvrOptions::kMaxC, "(0, 1e6]") ||
      !within(sigma, SvrOptions::kMinSigma, SvrOptions::kMaxSigma, "[0.001, 1000]") ||
      (epsilon && !within(*epsilon, 0.0, SvrOptions::kMaxEpsilon, "[0, 1e6]"))) {
    return false;
  }
  if (!cuckoo.IsValid(error)) return false;
  if (grid_budget && *grid_budget < 4) {
    if (error) *error = "SvrSearchOptions::grid_budget = " + std::to_string(*grid_budget) + ": must be >= 4";
    return false;
  }
  return true;
}

bool DriftFitOptions::IsValid(std::string* error) const {
  if (!rate.IsValid(error) || !state.IsValid(error) || !auto_select.IsValid(error) ||
      !polynomial.IsValid(error) || !svr.IsValid(error) || !search.IsValid(error))
    return false;
  if (train_period_s && (!(*train_period_s > 0.0) || !std::isfinite(*train_period_s))) {
    if (error) *error = "DriftFitOptions::train_period_s = " + FormatNumber(*train_period_s) + ": must be > 0";
    return false;
  }
  if (max_train_samples < 10) {
    if (error)
      *error = "DriftFitOptions::max_train_samples = " + std::to_string(max_train_samples) + ": must be >= 10";
    return false;
  }
  if (cv_folds < 2) {
    if (error) *error = "DriftFitOptions::cv_folds = " + std::to_string(cv_folds) + ": must be >= 2";
    return false;
  }
  if (!noise_psd.IsValid(error)) return false;
  if (noise_model == DriftNoiseModel::kAllan && model != DriftModelKind::kPolynomial) {
    if (error)
      *error = std::string("DriftFitOptions::noise_model = allan applies to model poly only, got ") +
               DriftModelKindName(model);
    return false;
  }
  if (!(gls_block_s > 0.0) || !std::isfinite(gls_block_s)) {
    if (error) *error = "DriftFitOptions::gls_block_s = " + FormatNumber(gls_block_s) + ": must be > 0";
    return false;
  }
  if (max_gls_blocks < 10) {
    if (error) *error = "DriftFitOptions::max_gls_blocks = " + std::to_string(max_gls_blocks) + ": must be >= 10";
    return false;
  }
  return true;
}

std::string DriftFitSummary::BriefReport() const {
  std::ostringstream s;
  s << "drift model " << DriftModelKindName(model) << " (" << DriftInputSetName(inputs) << " -> "
    << target_name << "): " << num_samples << " samples at " << fs_hz << " Hz, trained on "
    << num_train << " (" << train_period_s << " s means), T in [" << temp_min_c << ", "
    << temp_max_c << "] C";
  if (C) s << ", C = " << *C << ", sigma = " << *sigma << ", epsilon = " << *epsilon
           << ", " << num_support << " SVs";
  if (model == DriftModelKind::kPolynomial || model == DriftModelKind::kHybrid) {
    s << ", degree " << degree;
    if (inputs != DriftInputSet::kTemp) s << " (+ state degree " << dtemp_degree << ")";
    if (gain_temp_degree > 0) s << " (state gain of degree " << gain_temp_degree << " in T)";
  }
  if (lag_tau_s) s << ", lag tau = " << *lag_tau_s << " s";
  s << "; CV RMSE (" << DriftCvSchemeName(cv_scheme) << ", " << cv_folds << " folds";
  if (cv_scheme == DriftCvScheme::kThermalSegments) s << " over " << cv_segments << " thermal segments";
  s << ") = " << cv_rmse;
  if (drift_span > 0.0) s << " (" << FormatNumber(100.0 * cv_rmse / drift_span, 3) << "% of the drift span " << FormatNumber(drift_span, 4) << ")";
  s << ", train RMSE = " << train_rmse;
  if (evaluations > 0) s << ", " << evaluations << " parameter sets tried";
  s << ", " << fit_time_s << " s";
  if (noise_psd) s << "\nnoise model allan (generalised least squares): " << noise_psd->BriefReport();
  if (!kernel_decision.empty()) s << "\n" << kernel_decision;
  if (!selection_reason.empty()) s << "\n" << selection_reason;
  if (!identifiability.empty()) s << "\n" << identifiability;
  if (!data_support.empty()) s << "\npoints: " << data_support;
  for (const ExcludedTerm& e : excluded_terms)
    s << "\nleft out: " << e.term << ": " << e.reason << "; would be identified by " << e.would_identify;
  if (drift_span > 0.0 && cv_rmse > drift_span)
    s << "\nwarning: the CV RMSE exceeds the drift span: a left-out segment lay outside what the rest of the run "
         "covers and the model extrapolated there; expect errors of that size on such a run";
  return s.str();
}

std::string TemperatureExcursion::Message() const {
  if (!outside) return "";
  std::ostringstream s;
  s << "temperature outside the fitted range for " << 100.0 * fraction_outside << "% of samples";
  if (below_c > 0.0) s << ", down to " << below_c << " C below its minimum";
  if (above_c > 0.0) s << ", up to " << above_c << " C above its maximum";
  s << ": the model extrapolates there";
  return s.str();
}

namespace drift_internal {

Result<Columns> BuildFeatures(const DriftInputs& inputs, DriftInputSet set, const TemperatureRateOptions& rate,
                              const ThermalStateOptions& state, bool causal) {
  if (inputs.temp_c.empty()) return InvalidInput("drift model: empty temperature record");
  for (std::size_t i = 0; i < inputs.temp_c.size(); ++i)
    if (!std::isfinite(inputs.temp_c[i]))
      return InvalidInput("drift model: non-finite temperature at sample " + std::to_string(i));
  Columns x = {std::vector<double>(inputs.temp_c.begin(), inputs.temp_c.end())};
  if (set != DriftInputSet::kTemp) {
    auto r = ComputeThermalState(inputs.temp_c, inputs.fs_hz, set, rate, state, causal);
    if (!r.ok()) return r.error();
    x.push_back(std::move(*r));
  }
  if (HasSecondMemoryState(set)) {  // temp,dtemp,memory: the memory of Eq. TS-3 as column 2
    auto m = ComputeThermalState(inputs.temp_c, inputs.fs_hz, DriftInputSet::kTempAndMemory, rate, state, true);
    if (!m.ok()) return m.error();
    x.push_back(std::move(*m));
  }
  return x;
}

std::vector<double> BlockMeans(std::span<const double> x, std::size_t block) {
  std::vector<double> out;
  if (block <= 1) return std::vector<double>(x.begin(), x.end());
  for (std::size_t a = 0; a < x.size(); a += block) {
    const std::size_t b = std::min(x.size(), a + block);
    double s = 0.0;
    for (std::size_t i = a; i < b; ++i) s += x[i];
    out.push_back(s / static_cast<double>(b - a));
  }
  return out;
}

}  // namespace drift_internal

using drift_internal::Columns;

double DriftModel::EffectiveTemp(double temp_c) const {
  if (out_of_range == OutOfRangePolicy::kClamp) return std::clamp(temp_c, summary.temp_min_c, summary.temp_max_c);
  return temp_c;
}

double DriftModel::PredictAt(double temp_c, double state, double memory) const {
  const double t = EffectiveTemp(temp_c);
  double f = 0.0;
  if (structured) f += structured->PredictOne(t, state, memory);
  if (kernel) {
    const double x[3] = {t, state, memory};
    f += kernel->PredictOne(std::span<const double>(x, kernel->num_inputs));
  }
  return f;
}

Result<std::vector<double>> DriftModel::Predict(const DriftInputs& in, bool causal) const {
  auto features = drift_internal::BuildFeatures(in, inputs, rate, state, causal);
  if (!features.ok()) return features.error();
  if (out_of_range == OutOfRangePolicy::kClamp)
    for (double& t : (*features)[0]) t = EffectiveTemp(t);
  // One part: its own batch prediction (bit-identical to version 1 for poly and SVR models).
  if (structured && !kernel) return structured->Predict(*features);
  if (kernel && !structured) return kernel->Predict(*features);
  if (!structured) return InvalidArgument("drift model: no structured part and no kernel part");
  std::vector<double> f = structured->Predict(*features);
  const std::vector<double> k = kernel->Predict(*features);
  for (std::size_t i = 0; i < f.size(); ++i) f[i] += k[i];
  return f;
}

TemperatureExcursion DriftModel::CheckTemperatureRange(std::span<const double> temp_c) const {
  TemperatureExcursion e;
  std::size_t count = 0;
  for (double t : temp_c) {
    if (t < summary.temp_min_c) {
      ++count;
      e.below_c = std::max(e.below_c, summary.temp_min_c - t);
    } else if (t > summary.temp_max_c) {
      ++count;
      e.above_c = std::max(e.above_c, t - summary.temp_max_c);
    }
  }
  e.outside = count > 0;
  e.fraction_outside = temp_c.empty() ? 0.0 : static_cast<double>(count) / static_cast<double>(temp_c.size());
  return e;
}

}  // namespace gyrocomp
