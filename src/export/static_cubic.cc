// The static curve with every temperature weighted alike (see static_cubic.h).
#include "gyrocomp/export/static_cubic.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace gyrocomp {

bool StaticCubicOptions::IsValid(std::string* error) const {
  if (bins < 8 || bins > 1000000) {
    if (error) *error = "StaticCubicOptions::bins must be in [8, 1000000]";
    return false;
  }
  for (const auto& v : {temp_min_c, temp_max_c, ref_temp_c})
    if (v && !std::isfinite(*v)) {
      if (error) *error = "StaticCubicOptions: non-finite temperature";
      return false;
    }
  return true;
}

Result<TemperatureCubic> FitStaticCubicByTemperature(const DriftModel& model, const DriftInputs& run,
                                                     std::span<const double> y, const StaticCubicOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  const std::size_t n = run.temp_c.size();
  if (y.size() != n) return InvalidArgument("static cubic: values and temperatures differ in length");
  if (n == 0) return InvalidInput("static cubic: no samples");
  const auto [lo_it, hi_it] = std::minmax_element(run.temp_c.begin(), run.temp_c.end());
  TemperatureCubic c;
  c.temp_min_c = o.temp_min_c.value_or(*lo_it);
  c.temp_max_c = o.temp_max_c.value_or(*hi_it);
  c.ref_temp_c = o.ref_temp_c.value_or(0.5 * (c.temp_min_c + c.temp_max_c));
  const double span = c.temp_max_c - c.temp_min_c;
  if (!(span > 0.0) || !std::isfinite(span)) return InvalidInput("static cubic: empty or non-finite temperature range");
  // The model's dynamic part: its prediction on the run minus its curve at state 0.
  auto pred = model.Predict(run);
  if (!pred.ok()) return pred.error();
  std::vector<double> sum_t(static_cast<std::size_t>(o.bins), 0.0), sum_r(sum_t.size(), 0.0), count(sum_t.size(), 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = run.temp_c[i];
    const double r = y[i] - ((*pred)[i] - model.PredictAt(t, 0.0));
    if (!std::isfinite(t) || !std::isfinite(r)) return InvalidInput("static cubic: non-finite value at sample " + std::to_string(i));
    // resampleWithDeltaX: below the range -> bin 0, at or above its top -> the last bin.
    const double u = (t - c.temp_min_c) / span * o.bins;
    const auto b = static_cast<std::size_t>(std::clamp(std::floor(u), 0.0, static_cast<double>(o.bins - 1)));
    sum_t[b] += t, sum_r[b] += r, count[b] += 1.0;
  }
  // Least squares on the bin means, dT scaled by the half-span (conditioning).
  const double half = 0.5 * span;
  Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
  Eigen::Vector4d atb = Eigen::Vector4d::Zero();
  int used = 0;
  for (std::size_t b = 0; b < count.size(); ++b) {
    if (count[b] == 0.0) continue;
    const double x = (sum_t[b] / count[b] - c.ref_temp_c) / half;
    const Eigen::Vector4d a(1.0, x, x * x, x * x * x);
    ata += a * a.transpose();
    atb += a * (sum_r[b] / count[b]);
    ++used;
  }
  if (used < 4) return InvalidInput("static cubic: " + std::to_string(used) + " temperature bins hold samples, need >= 4");
  const Eigen::Vector4d k = ata.ldlt().solve(atb);
  for (int j = 0; j < 4; ++j) c.coeff[static_cast<std::size_t>(j)] = k[j] / std::pow(half, j);
  for (double v : c.coeff)
    if (!std::isfinite(v)) return InvalidInput("static cubic: non-finite coefficient (degenerate temperatures)");
  return c;
}

}  // namespace gyrocomp
