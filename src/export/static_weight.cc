// Which estimator of the static curve to export, per axis (see static_weight.h).
#include "gyrocomp/export/static_weight.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "gyrocomp/core/format.h"
#include "gyrocomp/drift/noise_model.h"
#include "gyrocomp/drift/temperature_rate.h"

namespace gyrocomp {

std::optional<StaticWeight> ParseStaticWeight(std::string_view name) {
  if (name == "temperature") return StaticWeight::kTemperature;
  if (name == "time") return StaticWeight::kTime;
  if (name == "auto") return StaticWeight::kAuto;
  return std::nullopt;
}

const char* StaticWeightName(StaticWeight weight) {
  switch (weight) {
    case StaticWeight::kTemperature: return "temperature";
    case StaticWeight::kTime: return "time";
    case StaticWeight::kAuto: return "auto";
  }
  return "?";
}

bool StaticWeightOptions::IsValid(std::string* error) const {
  if (bins < 8 || bins > 1000000 || grid_points < 8 || grid_points > 100000) {
    if (error) *error = "StaticWeightOptions: bins must be in [8, 1000000] and grid_points in [8, 100000]";
    return false;
  }
  if (!(min_heating_c_per_s > 0.0) || !std::isfinite(min_heating_c_per_s) || !(red_block_s > 0.0) ||
      !std::isfinite(red_block_s)) {
    if (error) *error = "StaticWeightOptions: min_heating_c_per_s and red_block_s must be finite and > 0";
    return false;
  }
  return true;
}

namespace {

using Row = Eigen::Vector4d;
Row Design(double x) { return Row(1.0, x, x * x, x * x * x); }

// The two estimators as 4 x n maps from the run's values to the cubic's coefficients in
// x = (T - ref) / half.
struct Estimators {
  Eigen::MatrixXd time, temperature;
};

Result<Estimators> BuildEstimators(const std::vector<double>& x, double lo_x, double hi_x, int bins) {
  const auto n = static_cast<Eigen::Index>(x.size());
  Estimators e{Eigen::MatrixXd(4, n), Eigen::MatrixXd(4, n)};
  // time: ordinary least squares over every sample.
  Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
  for (double v : x) ata += Design(v) * Design(v).transpose();
  const Eigen::Matrix4d inv_time = ata.inverse();
  // temperature: least squares on the bin means (static_cubic.cc, resampleWithDeltaX binning).
  std::vector<double> sum_x(static_cast<std::size_t>(bins), 0.0), count(sum_x.size(), 0.0);
  std::vector<std::size_t> bin(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double u = (x[i] - lo_x) / (hi_x - lo_x) * bins;
    bin[i] = static_cast<std::size_t>(std::clamp(std::floor(u), 0.0, static_cast<double>(bins - 1)));
    sum_x[bin[i]] += x[i], count[bin[i]] += 1.0;
  }
  Eigen::Matrix4d btb = Eigen::Matrix4d::Zero();
  int used = 0;
  for (std::size_t b = 0; b < count.size(); ++b)
    if (count[b] > 0.0) btb += Design(sum_x[b] / count[b]) * Design(sum_x[b] / count[b]).transpose(), ++used;
  if (used < 4) return InvalidInput("static weight: " + std::to_string(used) + " temperature bins hold samples, need >= 4");
  const Eigen::Matrix4d inv_temp = btb.inverse();
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    e.time.col(i) = inv_time * Design(x[k]);
    e.temperature.col(i) = inv_temp * Design(sum_x[bin[k]] / count[bin[k]]) / count[bin[k]];
  }
  if (!e.time.allFinite() || !e.temperature.allFinite()) return InvalidInput("static weight: degenerate temperatures");
  return e;
}

// Cov of L n under the band's noise: white per sample plus the red part as block means.
Eigen::Matrix4d NoiseCovariance(const Eigen::MatrixXd& l, const NoisePsd& psd, double fs_hz, double block_s,
                                double duration_s) {
  const Eigen::Matrix4d white = (psd.h0 * fs_hz / 2.0) * (l * l.transpose());
  const auto per_block = static_cast<Eigen::Index>(std::max(1.0, std::round(block_s * fs_hz)));
  const Eigen::Index n = l.cols();
  const Eigen::Index blocks = (n + per_block - 1) / per_block;
  Eigen::MatrixXd lb = Eigen::MatrixXd::Zero(4, blocks);
  for (Eigen::Index i = 0; i < n; ++i) lb.col(i / per_block) += l.col(i);
  NoisePsd red = psd;
  red.h0 = 0.0;
  // Eq. G-2 with the red part held flat below the longest Allan tau fitted (drift_band.cc).
  const double f_floor_hz = RedSpectrumFloorHz(NoisePsdOptions{}, duration_s);
  const std::vector<double> r =
      BlockMeanAutocovariance(red, static_cast<std::size_t>(blocks), static_cast<double>(per_block) / fs_hz, f_floor_hz);
  Eigen::MatrixXd sigma(blocks, blocks);
  for (Eigen::Index i = 0; i < blocks; ++i)
    for (Eigen::Index j = 0; j < blocks; ++j) sigma(i, j) = r[static_cast<std::size_t>(std::abs(i - j))];
  return white + lb * sigma * lb.transpose();
}

// Mean squares over one condition's points (x, next run's dT/dt): the gain part and the noise
// part of estimator `l`, the constant removed.
struct MeanSquares {
  double gain = 0.0, noise = 0.0;
};
MeanSquares Condition(const Eigen::MatrixXd& l, const Eigen::Matrix4d& cov, const Eigen::VectorXd& rate_run, double g,
                      const std::vector<double>& x, const std::vector<double>& r_next) {
  MeanSquares m;
  if (x.empty()) return m;
  const Row k = l * rate_run;  // what the estimator makes of the run's dT/dt
  const auto n = static_cast<double>(x.size());
  double mean_bias = 0.0;
  Row mean_a = Row::Zero();
  for (std::size_t i = 0; i < x.size(); ++i) mean_bias += (Design(x[i]).dot(k) - r_next[i]) / n, mean_a += Design(x[i]) / n;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double bias = g * (Design(x[i]).dot(k) - r_next[i] - mean_bias);
    const Row a = Design(x[i]) - mean_a;
    m.gain += bias * bias / n;
    m.noise += a.dot(cov * a) / n;
  }
  return m;
}

// `m.gain`: the mean square of the rate shape (per unit gain), C/s^2.
StaticEstimatorError ErrorOf(MeanSquares m, double gain) {
  StaticEstimatorError e;
  e.rate_shape_rms = std::sqrt(std::max(0.0, m.gain));
  e.rate_gain_rms = gain * e.rate_shape_rms;
  e.noise_rms = std::sqrt(std::max(0.0, m.noise));
  e.total_rms = std::hypot(e.rate_gain_rms, e.noise_rms);
  return e;
}

void Decide(StaticWeightChoice* c, const std::string& evidence) {
  c->chosen = c->temperature.total_rms < c->time.total_rms ? StaticWeight::kTemperature : StaticWeight::kTime;
  c->reason = std::string(StaticWeightName(c->chosen)) + ": expected error time " + FormatNumber(c->time.total_rms, 3) +
              " (gain " + FormatNumber(c->time.rate_gain_rms, 3) + ", noise " + FormatNumber(c->time.noise_rms, 3) + "), temperature " +
              FormatNumber(c->temperature.total_rms, 3) + " (gain " + FormatNumber(c->temperature.rate_gain_rms, 3) + ", noise " +
              FormatNumber(c->temperature.noise_rms, 3) + ")" + evidence;
}

}  // namespace

Result<StaticWeightChoice> ChooseStaticWeight(const DriftModel& model, const DriftInputs& run, double temp_min_c,
                                              double temp_max_c, CubicCondition condition,
                                              const StaticWeightOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  if (!model.band) return InvalidInput("drift model: no prediction band (the model file predates prediction bands; refit it)");
  const double span = temp_max_c - temp_min_c;
  if (!(span > 0.0) || !std::isfinite(span)) return InvalidInput("static weight: empty or non-finite temperature range");
  if (!(run.fs_hz > 0.0) || run.temp_c.size() < 8) return InvalidInput("static weight: fewer than 8 samples or fs <= 0");
  const double ref = 0.5 * (temp_min_c + temp_max_c), half = 0.5 * span;
  std::vector<double> x(run.temp_c.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = (run.temp_c[i] - ref) / half;
    if (!std::isfinite(x[i])) return InvalidInput("static weight: non-finite temperature at sample " + std::to_string(i));
  }
  auto est = BuildEstimators(x, -1.0, 1.0, o.bins);
  if (!est.ok()) return est.error();
  auto rate = TemperatureRate(run.temp_c, run.fs_hz, model.rate);
  if (!rate.ok()) return rate.error();
  const Eigen::VectorXd r = Eigen::Map<const Eigen::VectorXd>(rate->data(), static_cast<Eigen::Index>(rate->size()));
  // The conditions' points: steady (a grid over the range, dT/dt 0), warm-up (the run's heating).
  std::vector<double> steady_x, steady_r, warm_x, warm_r;
  for (int i = 0; i < o.grid_points; ++i) steady_x.push_back(-1.0 + 2.0 * i / (o.grid_points - 1)), steady_r.push_back(0.0);
  for (std::size_t i = 0; i < x.size(); ++i)
    if ((*rate)[i] >= o.min_heating_c_per_s) warm_x.push_back(std::clamp(x[i], -1.0, 1.0)), warm_r.push_back((*rate)[i]);
  if (warm_x.empty()) condition = CubicCondition::kSteady;
  StaticWeightChoice c;
  // The squared gain: the unbiased estimate g^2 - SE^2 (Eq. I-1's gain and jackknife SE), not the
  // band's |g| (Eq. B-4, expectation g^2 + SE^2): the noise part below already holds the noise's
  // share of the gain (the time estimator's variance is that of the model with the gain, minus
  // SE^2 (L r)(L r)'), so the band's figure would count SE^2 once more. A model file keeps only
  // the band's G: then that.
  const DriftFitSummary& fs = model.summary;
  c.rate_gain_rms = c.band_gain_rms = model.band->unidentified_rate_gain_rms;
  std::string gain_source = "the band's G = |g| (Eq. B-4)";
  if (fs.unidentified_rate_gain && fs.unidentified_rate_gain_se) {
    const double g = *fs.unidentified_rate_gain, se = *fs.unidentified_rate_gain_se;
    c.gain = g, c.gain_se = se;
    c.rate_gain_rms = std::min(c.rate_gain_rms, std::sqrt(std::max(0.0, g * g - se * se)));
    gain_source = "sqrt(max(0, g^2 - SE^2)), g " + FormatNumber(g, 3) + " +- " + FormatNumber(se, 3);
  }
  const double duration_s = static_cast<double>(x.size()) / run.fs_hz;
  // The band's block period (drift_band.cc AttachBand): red_block_s, at least 20 blocks.
  const double block_s = std::max(1.0 / run.fs_hz, std::min(o.red_block_s, duration_s / 20.0));
  for (auto [l, out] : {std::pair{&est->time, &c.time}, std::pair{&est->temperature, &c.temperature}}) {
    const Eigen::Matrix4d cov = NoiseCovariance(*l, model.band->noise, run.fs_hz, block_s, duration_s);
    const MeanSquares s = Condition(*l, cov, r, 1.0, steady_x, steady_r);
    const MeanSquares w = Condition(*l, cov, r, 1.0, warm_x, warm_r);
    MeanSquares m = s;
    if (condition == CubicCondition::kWarmUp) m = w;
    if (condition == CubicCondition::kBoth) m = {0.5 * (s.gain + w.gain), 0.5 * (s.noise + w.noise)};
    *out = ErrorOf(m, c.rate_gain_rms);
    if (!std::isfinite(out->total_rms)) return InvalidInput("static weight: non-finite expected error");
  }
  Decide(&c, "; left-out dT/dt gain " + FormatNumber(c.rate_gain_rms, 3) + " per C/s (" + gain_source + ")");
  return c;
}

StaticWeightChoice CombineStaticWeightChoices(const std::vector<StaticWeightChoice>& per_run) {
  StaticWeightChoice c;
  if (per_run.empty()) return c;
  const auto k = static_cast<double>(per_run.size());
  MeanSquares t, p;
  double g2 = 0.0, g_sum = 0.0, se2 = 0.0, band2 = 0.0;
  bool all_gains = true;
  for (const StaticWeightChoice& r : per_run) {
    t.gain += r.time.rate_shape_rms * r.time.rate_shape_rms / k, t.noise += r.time.noise_rms * r.time.noise_rms / (k * k);
    p.gain += r.temperature.rate_shape_rms * r.temperature.rate_shape_rms / k;
    p.noise += r.temperature.noise_rms * r.temperature.noise_rms / (k * k);
    g2 += r.rate_gain_rms * r.rate_gain_rms / k;
    band2 += r.band_gain_rms * r.band_gain_rms / k;
    all_gains &= r.gain && r.gain_se;
    if (r.gain && r.gain_se) g_sum += *r.gain, se2 += *r.gain_se * *r.gain_se / (k * k);
  }
  std::string source = "the runs' mean squared gain";
  if (all_gains) {
    const double g = g_sum / k;
    c.gain = g, c.gain_se = std::sqrt(se2);
    g2 = std::min(band2, std::max(0.0, g * g - se2));
    source = "the runs' mean gain " + FormatNumber(g, 3) + " +- " + FormatNumber(std::sqrt(se2), 3) + ", sqrt(max(0, g^2 - SE^2))";
  }
  c.rate_gain_rms = std::sqrt(g2);
  c.band_gain_rms = std::sqrt(band2);
  c.time = ErrorOf(t, c.rate_gain_rms), c.temperature = ErrorOf(p, c.rate_gain_rms);
  Decide(&c, "; " + std::to_string(per_run.size()) + " runs averaged: noise / runs, left-out dT/dt gain " +
                 FormatNumber(c.rate_gain_rms, 3) + " per C/s (" + source + ")");
  return c;
}

}  // namespace gyrocomp
