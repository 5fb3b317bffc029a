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

Result<TemperatureCubic> ProjectOntoCubic(const DriftModel& model, const CubicProjectionOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  TemperatureCubic cubic;
  cubic.temp_min_c = options.temp_min_c.value_or(model.summary.temp_min_c);
  cubic.temp_max_c = options.temp_max_c.value_or(model.summary.temp_max_c);
  if (!(cubic.temp_min_c < cubic.temp_max_c)) {
    std::ostringstream s;
    s << "cubic projection: empty temperature range [" << cubic.temp_min_c << ", " << cubic.temp_max_c << "] C";
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
    y(i) = EvaluateDriftModel(model, t_model, 0.0);
  }
  const Eigen::Vector4d c = a.colPivHouseholderQr().solve(y);
  for (int k = 0; k < 4; ++k) cubic.coeff[k] = c(k) / std::pow(h, k);
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
