// Scores of an exported firmware cubic (see cubic_score.h).
#include "gyrocomp/export/cubic_score.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "gyrocomp/drift/temperature_rate.h"
#include "gyrocomp/export/param_export.h"

namespace gyrocomp {

// By bisection on erf.
double TwoSidedZ(double level) {
  double lo = 0.0, hi = 10.0;
  for (int k = 0; k < 100; ++k) {
    const double mid = 0.5 * (lo + hi);
    (std::erf(mid / std::sqrt(2.0)) < level ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

namespace {

// PX4 TemperatureCompensation.cpp calc_thermal_offsets_3D (float arithmetic, T clamped to
// [TMIN, TMAX], delta_temp = T - TREF, X0 + X1 dT + X2 dT^2 + X3 dT^3).
float Px4Offset(const TemperatureCubic& c, float temp_c) {
  const float t = std::clamp(temp_c, static_cast<float>(c.temp_min_c), static_cast<float>(c.temp_max_c));
  const float dt = t - static_cast<float>(c.ref_temp_c);
  const float x0 = static_cast<float>(c.coeff[0]), x1 = static_cast<float>(c.coeff[1]);
  const float x2 = static_cast<float>(c.coeff[2]), x3 = static_cast<float>(c.coeff[3]);
  return x0 + x1 * dt + x2 * dt * dt + x3 * dt * dt * dt;
}

// AP_InertialSensor_tempcal.cpp polynomial_eval: (c0 + (c1 + c2 x) x) x, coefficients x 1e-6.
float ArduPilotPoly(const std::array<float, 3>& c, float x) {
  return (c[0] + (c[1] + c[2] * x) * x) * x * 1.0e-6f;
}

}  // namespace

std::vector<double> FirmwareCorrection(FirmwareFormula formula, const TemperatureCubic& cubic,
                                       std::span<const double> temp_c, double cal_temp_c) {
  std::vector<double> out(temp_c.size());
  if (formula == FirmwareFormula::kPx4) {
    for (std::size_t i = 0; i < temp_c.size(); ++i) out[i] = Px4Offset(cubic, static_cast<float>(temp_c[i]));
    return out;
  }
  const std::array<double, 3> g = ArduPilotGyrCoefficients(cubic);
  const std::array<float, 3> c = {static_cast<float>(g[0]), static_cast<float>(g[1]), static_cast<float>(g[2])};
  const float tmin = static_cast<float>(cubic.temp_min_c), tmax = static_cast<float>(cubic.temp_max_c);
  const float ref = static_cast<float>(kArduPilotTcalReferenceC);
  const float tcal = std::clamp(static_cast<float>(cal_temp_c), tmin, tmax);
  const float at_cal = ArduPilotPoly(c, tcal - ref);
  for (std::size_t i = 0; i < temp_c.size(); ++i) {
    const float t = std::clamp(static_cast<float>(temp_c[i]), tmin, tmax);
    out[i] = ArduPilotPoly(c, t - ref) - at_cal;
  }
  return out;
}

Result<double> ResidualBlockRms(std::span<const double> value, std::span<const double> correction,
                                std::size_t block_rows) {
  if (value.size() != correction.size()) return InvalidArgument("ResidualBlockRms: value and correction sizes differ");
  if (block_rows == 0) return InvalidArgument("ResidualBlockRms: block_rows must be >= 1");
  const std::size_t blocks = value.size() / block_rows;
  if (blocks < 2)
    return InvalidInput("residual block means: " + std::to_string(value.size()) + " rows make fewer than 2 blocks of " +
                        std::to_string(block_rows));
  std::vector<double> means(blocks, 0.0);
  for (std::size_t b = 0; b < blocks; ++b) {
    for (std::size_t i = b * block_rows; i < (b + 1) * block_rows; ++i) means[b] += value[i] - correction[i];
    means[b] /= static_cast<double>(block_rows);
  }
  double mean = 0.0;
  for (double m : means) mean += m / static_cast<double>(blocks);
  double ss = 0.0;
  for (double m : means) ss += (m - mean) * (m - mean);
  const double rms = std::sqrt(ss / static_cast<double>(blocks));
  if (!std::isfinite(rms)) return InvalidInput("residual block means: non-finite values");
  return rms;
}

bool CubicExpectedErrorOptions::IsValid(std::string* error) const {
  if (grid_points < 8 || grid_points > 100000) {
    if (error) *error = "CubicExpectedErrorOptions::grid_points must be in [8, 100000]";
    return false;
  }
  if (!(min_heating_c_per_s > 0.0) || !std::isfinite(min_heating_c_per_s)) {
    if (error) *error = "CubicExpectedErrorOptions::min_heating_c_per_s must be finite and > 0 C/s";
    return false;
  }
  return true;
}

namespace {

// Accumulates (cubic - model)^2 and sd^2 over the samples `use` selects.
CubicConditionError Summarise(const std::vector<double>& proj, const std::vector<double>& band_sd, const std::vector<bool>& use) {
  CubicConditionError e;
  double ss_proj = 0.0, ss_sd = 0.0;
  for (std::size_t i = 0; i < proj.size(); ++i) {
    if (!use[i]) continue;
    const double sd = band_sd[i];
    ss_proj += proj[i] * proj[i];
    ss_sd += sd * sd;
    ++e.num_samples;
  }
  if (e.num_samples == 0) return e;
  const double n = static_cast<double>(e.num_samples);
  e.projection_rms = std::sqrt(ss_proj / n);
  e.band_sd_rms = std::sqrt(ss_sd / n);
  e.total_rms = std::hypot(e.projection_rms, e.band_sd_rms);
  return e;
}

// Steady: every grid temperature alike (CubicErrorProfile).
Result<CubicConditionError> SteadyError(const DriftModel& m, const TemperatureCubic& c, int points) {
  auto p = SteadyCubicErrorProfile(m, c, points);
  if (!p.ok()) return p.error();
  return Summarise(p->projection, p->band_sd, std::vector<bool>(p->temp_c.size(), true));
}

// The calibration run's heating samples, the model's own prediction there (its state included).
Result<std::optional<CubicConditionError>> WarmUpError(const DriftModel& m, const TemperatureCubic& c, double z,
                                                       const DriftInputs& run, double min_heating) {
  auto band = m.PredictBand(run);
  if (!band.ok()) return band.error();
  auto rate = TemperatureRate(run.temp_c, run.fs_hz);
  if (!rate.ok()) return rate.error();
  std::vector<bool> use(run.temp_c.size());
  std::vector<double> proj(run.temp_c.size()), sd(run.temp_c.size());
  for (std::size_t i = 0; i < use.size(); ++i) {
    use[i] = (*rate)[i] >= min_heating;
    proj[i] = c.Evaluate(run.temp_c[i]) - band->center[i];
    sd[i] = (band->hi[i] - band->lo[i]) / (2.0 * z);
  }
  // The model's prediction carries the run's constant: compare about the heating samples' mean.
  double mean = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < use.size(); ++i)
    if (use[i]) mean += proj[i], ++n;
  if (n == 0) return std::optional<CubicConditionError>();
  mean /= static_cast<double>(n);
  for (double& p : proj) p -= mean;
  return std::optional<CubicConditionError>(Summarise(proj, sd, use));
}

}  // namespace

// Temperature held: a ramp over the cubic's range at 1e-5 C/s (dT/dt ~ 0, every lag settled).
Result<CubicErrorProfile> SteadyCubicErrorProfile(const DriftModel& m, const TemperatureCubic& c, int points) {
  if (!m.band) return InvalidInput("drift model: no prediction band (the model file predates prediction bands; refit it)");
  if (points < 2) return InvalidArgument("SteadyCubicErrorProfile: points must be >= 2");
  const double span = c.temp_max_c - c.temp_min_c;
  if (!(span > 0.0) || !std::isfinite(span)) return InvalidInput("expected error: empty or non-finite temperature range");
  CubicErrorProfile p;
  p.level = m.band->level;
  p.temp_c.resize(static_cast<std::size_t>(points));
  for (int i = 0; i < points; ++i) p.temp_c[static_cast<std::size_t>(i)] = c.temp_min_c + span * i / (points - 1);
  const double fs_hz = 1.0e-5 / (span / (points - 1));
  if (!std::isfinite(fs_hz)) return InvalidInput("expected error: temperature range too small for a steady ramp");
  auto band = m.PredictBand({p.temp_c, fs_hz});
  if (!band.ok()) return band.error();
  const double z = TwoSidedZ(p.level);
  for (std::size_t i = 0; i < p.temp_c.size(); ++i) {
    p.projection.push_back(c.Evaluate(p.temp_c[i]) - m.PredictAt(p.temp_c[i], 0.0));
    p.band_sd.push_back((band->hi[i] - band->lo[i]) / (2.0 * z));
  }
  return p;
}

Result<CubicExpectedError> ExpectedCubicError(const DriftModel& model, const TemperatureCubic& cubic,
                                              const std::optional<DriftInputs>& calibration_run,
                                              const CubicExpectedErrorOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (!model.band) return InvalidInput("drift model: no prediction band (the model file predates prediction bands; refit it)");
  CubicExpectedError e;
  e.level = model.band->level;
  const double z = TwoSidedZ(e.level);
  auto steady = SteadyError(model, cubic, options.grid_points);
  if (!steady.ok()) return steady.error();
  e.steady = *steady;
  if (calibration_run) {
    auto warm = WarmUpError(model, cubic, z, *calibration_run, options.min_heating_c_per_s);
    if (!warm.ok()) return warm.error();
    e.warm_up = *warm;
  }
  for (const CubicConditionError* c : {&e.steady, e.warm_up ? &*e.warm_up : &e.steady})
    if (!std::isfinite(c->total_rms)) return InvalidInput("expected error: non-finite band or prediction");
  return e;
}

}  // namespace gyrocomp
