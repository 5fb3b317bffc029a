// Least-squares projection of a drift model onto a cubic in temperature (see thermal_cubic.h).
#include "gyrocomp/export/thermal_cubic.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Dense>

#include "gyrocomp/export/causal_drift.h"

namespace gyrocomp {

double TemperatureCubic::Evaluate(double temp_c) const {
  // PX4 calc_thermal_offsets_3D: T clamped to [TMIN, TMAX], then the cubic in dT = T - TREF.
  const double dt = std::clamp(temp_c, temp_min_c, temp_max_c) - ref_temp_c;
  return coeff[0] + dt * (coeff[1] + dt * (coeff[2] + dt * coeff[3]));
}

TemperatureCubic TemperatureCubic::Scaled(double factor) const {
  TemperatureCubic c = *this;
  for (double& v : c.coeff) v *= factor;
  return c;
}

TemperatureCubic TemperatureCubic::Recentered(double new_ref_c) const {
  // sum_k c_k (x + d)^k = sum_j x^j sum_{k>=j} c_k binom(k, j) d^(k-j).
  static constexpr double kBinom[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
  const double d = new_ref_c - ref_temp_c;
  TemperatureCubic out = *this;
  out.ref_temp_c = new_ref_c;
  for (int j = 0; j < 4; ++j) {
    double b = 0.0;
    for (int k = j; k < 4; ++k) b += coeff[k] * kBinom[k][j] * std::pow(d, k - j);
    out.coeff[j] = b;
  }
  return out;
}

std::optional<CubicCondition> ParseCubicCondition(std::string_view name) {
  if (name == "steady") return CubicCondition::kSteady;
  if (name == "warm-up") return CubicCondition::kWarmUp;
  if (name == "both") return CubicCondition::kBoth;
  return std::nullopt;
}

const char* CubicConditionName(CubicCondition condition) {
  switch (condition) {
    case CubicCondition::kWarmUp: return "warm-up";
    case CubicCondition::kBoth: return "both";
    default: return "steady";
  }
}

double StateByTemperature::At(double temp_c) const {
  if (state.empty()) return 0.0;
  const double x = (temp_c - t0_c) / bin_c;
  const auto i = static_cast<long>(std::floor(x));
  if (i < 0) return state.front();
  if (static_cast<std::size_t>(i) >= state.size()) return state.back();
  return state[static_cast<std::size_t>(i)];
}

Result<StateByTemperature> HeatingStateByTemperature(std::span<const double> temp_c, std::span<const double> state,
                                                     std::span<const double> rate_c_per_s, double min_heating_c_per_s,
                                                     double bin_c) {
  if (!(bin_c > 0.0) || !std::isfinite(min_heating_c_per_s))
    return InvalidArgument("HeatingStateByTemperature: bin_c must be > 0 and min_heating_c_per_s finite");
  if (state.size() != temp_c.size() || rate_c_per_s.size() != temp_c.size())
    return InvalidArgument("HeatingStateByTemperature: temp_c, state and rate_c_per_s must be as long");
  StateByTemperature out;
  out.bin_c = bin_c;
  double lo = INFINITY, hi = -INFINITY;
  for (double t : temp_c)
    if (std::isfinite(t)) lo = std::min(lo, t), hi = std::max(hi, t);
  if (!(lo <= hi)) return out;
  out.t0_c = lo;
  std::vector<std::vector<double>> bins(static_cast<std::size_t>((hi - lo) / bin_c) + 1);
  for (std::size_t i = 0; i < temp_c.size(); ++i)
    if (std::isfinite(temp_c[i]) && std::isfinite(state[i]) && rate_c_per_s[i] >= min_heating_c_per_s)
      bins[static_cast<std::size_t>((temp_c[i] - lo) / bin_c)].push_back(state[i]);
  for (auto& b : bins) {
    if (b.empty()) {
      out.state.push_back(0.0);
      continue;
    }
    std::nth_element(b.begin(), b.begin() + static_cast<long>(b.size() / 2), b.end());
    out.state.push_back(b[b.size() / 2]);
  }
  return out;
}

Result<StateByTemperature> StateWhileHeating(const DriftModel& model, const DriftInputs& record,
                                             double min_heating_c_per_s, double bin_c) {
  if (!(bin_c > 0.0) || !std::isfinite(min_heating_c_per_s))
    return InvalidArgument("StateWhileHeating: bin_c must be > 0 and min_heating_c_per_s finite");
  if (model.inputs == DriftInputSet::kTemp || record.temp_c.empty()) {
    StateByTemperature out;
    out.bin_c = bin_c;
    return out;
  }
  auto rate = ComputeThermalState(record.temp_c, record.fs_hz, DriftInputSet::kTempAndRate, model.rate, model.state, false);
  if (!rate.ok()) return rate.error();
  auto state = ComputeThermalState(record.temp_c, record.fs_hz, model.inputs, model.rate, model.state, false);
  if (!state.ok()) return state.error();
  return HeatingStateByTemperature(record.temp_c, *state, *rate, min_heating_c_per_s, bin_c);
}

bool CubicProjectionOptions::IsValid(std::string* error) const {
  if (grid_points < 8) {
    if (error) *error = "CubicProjectionOptions::grid_points = " + std::to_string(grid_points) + ": must be >= 8";
    return false;
  }
  for (const auto& v : {temp_min_c, temp_max_c, ref_temp_c})
    if (v && !std::isfinite(*v)) {
      if (error) *error = "CubicProjectionOptions: temperatures must be finite";
      return false;
    }
  return true;
}

namespace {

// The curve the cubic is fitted to at temperature t (CubicCondition).
double ProjectionTarget(const DriftModel& model, const CubicProjectionOptions& o, double t) {
  const double steady = EvaluateDriftModel(model, t, 0.0);
  if (o.condition == CubicCondition::kSteady || model.inputs == DriftInputSet::kTemp) return steady;
  const double warm = EvaluateDriftModel(model, t, o.warm_up->At(t));
  return o.condition == CubicCondition::kWarmUp ? warm : 0.5 * (steady + warm);
}

}  // namespace

Result<TemperatureCubic> ProjectOntoCubic(const DriftModel& model, const CubicProjectionOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (options.condition != CubicCondition::kSteady && model.inputs != DriftInputSet::kTemp && !options.warm_up)
    return InvalidArgument(std::string("cubic projection for '") + CubicConditionName(options.condition) +
                           "': the model reads a thermal state, so the warm-up state by temperature is needed "
                           "(StateWhileHeating of the calibration run)");
  TemperatureCubic cubic;
  cubic.temp_min_c = options.temp_min_c.value_or(model.summary.temp_min_c);
  cubic.temp_max_c = options.temp_max_c.value_or(model.summary.temp_max_c);
  if (!(cubic.temp_min_c < cubic.temp_max_c)) {
    std::ostringstream s;
    s << "cubic projection: empty temperature range [" << cubic.temp_min_c << ", " << cubic.temp_max_c << "] C";
    return InvalidInput(s.str());
  }
  const double span_c = cubic.temp_max_c - cubic.temp_min_c;
  if (!std::isfinite(span_c)) {
    std::ostringstream s;
    s << "cubic projection: temperature range [" << cubic.temp_min_c << ", " << cubic.temp_max_c
      << "] C: its span is not a finite number";
    return InvalidInput(s.str());
  }
  cubic.ref_temp_c = options.ref_temp_c.value_or(0.5 * (cubic.temp_min_c + cubic.temp_max_c));
  // Static curve: thermal state 0 (dT/dt = 0, the lag settled, no heating/cooling memory).
  const int n = options.grid_points;
  // Columns in dT scaled by the half-range h (conditioning), coefficients rescaled after.
  const double h = 0.5 * (cubic.temp_max_c - cubic.temp_min_c);
  Eigen::MatrixXd a(n, 4);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) {
    const double t = cubic.temp_min_c + (cubic.temp_max_c - cubic.temp_min_c) * i / (n - 1);
    const double t_model = std::clamp(t, model.summary.temp_min_c, model.summary.temp_max_c);
    const double u = (t - cubic.ref_temp_c) / h;
    a(i, 0) = 1.0;
    a(i, 1) = u;
    a(i, 2) = u * u;
    a(i, 3) = u * u * u;
    y(i) = ProjectionTarget(model, options, t_model);
  }
  const Eigen::Vector4d c = a.colPivHouseholderQr().solve(y);
  for (int k = 0; k < 4; ++k) cubic.coeff[k] = c(k) / std::pow(h, k);
  // c_k is the fit's coefficient in u = dT / h divided by h^k: on a span of ~1e-100 C or less
  // (a model fitted on a constant temperature up to rounding) h^k underflows and c_k overflows.
  // No firmware cubic can hold it: refused, naming the span.
  for (int k = 0; k < 4; ++k) {
    if (!std::isfinite(cubic.coeff[k])) {
      std::ostringstream s;
      s << "cubic projection: temperature span " << span_c << " C ([" << cubic.temp_min_c << ", "
        << cubic.temp_max_c << "] C) is too narrow for a cubic in temperature: c" << k << " is not finite";
      return InvalidInput(s.str());
    }
  }
  return cubic;
}

std::string CubicProjectionCost::BriefReport() const {
  std::ostringstream s;
  s << "RMS(full model - cubic) = " << rms << ", max |.| = " << max_abs << " over " << num_samples
    << " samples (model span " << model_span << ")";
  return s.str();
}

Result<CubicProjectionCost> MeasureCubicProjectionCost(const DriftModel& model, const TemperatureCubic& cubic,
                                                       const DriftInputs& record) {
  auto full = model.Predict(record);
  if (!full.ok()) return full.error();
  CubicProjectionCost cost;
  cost.num_samples = full->size();
  double ss = 0.0;
  for (std::size_t i = 0; i < full->size(); ++i) {
    const double e = (*full)[i] - cubic.Evaluate(record.temp_c[i]);
    ss += e * e;
    cost.max_abs = std::max(cost.max_abs, std::abs(e));
  }
  cost.rms = full->empty() ? 0.0 : std::sqrt(ss / static_cast<double>(full->size()));
  const auto [lo, hi] = std::minmax_element(full->begin(), full->end());
  if (!full->empty()) cost.model_span = *hi - *lo;
  return cost;
}

}  // namespace gyrocomp
