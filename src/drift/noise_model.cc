// IEEE-952 noise model of a residual: Allan-variance fit (Eq. G-1) and the covariance of its
// block means (Eq. G-2). See noise_model.h.
#include "gyrocomp/drift/noise_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include <Eigen/Dense>

#include "gyrocomp/core/format.h"
#include "gyrocomp/core/units.h"

namespace gyrocomp {
namespace {

constexpr double kLn2 = std::numbers::ln2;
constexpr double kPi = std::numbers::pi;
// IEEE 952: the flicker floor of the ADEV is 0.664 B (0.664 = sqrt(2 ln2 / pi), as src/sim uses it).
constexpr double kFlickerFloor = 0.664;
// Reweighting passes of the Allan-variance fit (the weights converge in 2-3).
constexpr int kWeightIterations = 4;
// Aliases folded into the block-mean spectrum each side (Eq. G-2): the flicker's alias a adds
// ~1/a^3 of the main term; 200 leaves < 1e-5 of it out.
constexpr int kAliases = 200;

// Overlapping Allan variance of x at an averaging of m samples (tau = m / fs): half the mean
// square difference of adjacent m-sample means, over every start; c = prefix sums of x.
double OverlappingAvar(const std::vector<double>& c, std::size_t m) {
  const std::size_t n = c.size() - 1;
  double ss = 0.0;
  const std::size_t count = n - 2 * m + 1;
  for (std::size_t i = 0; i < count; ++i) {
    const double d = (c[i + 2 * m] - 2.0 * c[i + m] + c[i]) / static_cast<double>(m);
    ss += d * d;
  }
  return 0.5 * ss / static_cast<double>(count);
}

// Non-negative least squares of a 3-column problem by enumeration: every non-empty subset of the
// columns, unconstrained on it; the feasible (all >= 0) one with the smallest residual.
std::optional<NoisePsd> NonNegativeLeastSquares3(const Eigen::MatrixXd& a, const Eigen::VectorXd& b) {
  std::optional<NoisePsd> best;
  double best_ss = std::numeric_limits<double>::infinity();
  for (int mask = 1; mask < 8; ++mask) {
    std::vector<int> cols;
    for (int j = 0; j < 3; ++j)
      if (mask >> j & 1) cols.push_back(j);
    Eigen::MatrixXd sub(a.rows(), static_cast<Eigen::Index>(cols.size()));
    for (std::size_t j = 0; j < cols.size(); ++j) sub.col(static_cast<Eigen::Index>(j)) = a.col(cols[j]);
    const Eigen::VectorXd h = sub.colPivHouseholderQr().solve(b);
    if ((h.array() < 0.0).any() || !h.allFinite()) continue;
    const double ss = (sub * h - b).squaredNorm();
    if (ss >= best_ss) continue;
    best_ss = ss;
    double v[3] = {0.0, 0.0, 0.0};
    for (std::size_t j = 0; j < cols.size(); ++j) v[cols[j]] = h(static_cast<Eigen::Index>(j));
    best = NoisePsd{v[0], v[1], v[2]};
  }
  return best;
}

}  // namespace

std::optional<DriftNoiseModel> ParseDriftNoiseModel(std::string_view name) {
  if (name == "white") return DriftNoiseModel::kWhite;
  if (name == "allan") return DriftNoiseModel::kAllan;
  return std::nullopt;
}

const char* DriftNoiseModelName(DriftNoiseModel model) { return model == DriftNoiseModel::kAllan ? "allan" : "white"; }

double NoisePsd::arw_deg_per_sqrt_h() const { return units::DegPerSqrtSecToDegPerSqrtHour(std::sqrt(h0 / 2.0)); }

double NoisePsd::bias_instability_deg_per_h() const {
  return units::DpsToDph(std::sqrt(2.0 * kLn2 * h_1) / kFlickerFloor);
}

double NoisePsd::rrw_deg_per_h_per_sqrt_h() const {
  return units::DpsPerSqrtSecToDphPerSqrtHour(kPi * std::sqrt(2.0 * h_2));
}

std::string NoisePsd::BriefReport() const {
  std::ostringstream s;
  s << "S(f) = " << FormatNumber(h0, 4) << " + " << FormatNumber(h_1, 4) << "/f + " << FormatNumber(h_2, 4) << "/f^2 (target units^2/Hz; for deg/s: ARW "
    << FormatNumber(arw_deg_per_sqrt_h(), 4) << " deg/sqrt(h), bias instability " << FormatNumber(bias_instability_deg_per_h(), 4)
    << " deg/h, RRW " << FormatNumber(rrw_deg_per_h_per_sqrt_h(), 4) << " deg/h/sqrt(h))";
  return s.str();
}

bool NoisePsdOptions::IsValid(std::string* error) const {
  if (!(max_tau_fraction > 0.0 && max_tau_fraction <= 0.5)) {
    if (error) *error = "NoisePsdOptions::max_tau_fraction = " + FormatNumber(max_tau_fraction, 4) + ": must be in (0, 0.5]";
    return false;
  }
  if (min_tau_s && !(*min_tau_s > 0.0 && std::isfinite(*min_tau_s))) {
    if (error) *error = "NoisePsdOptions::min_tau_s = " + FormatNumber(*min_tau_s, 4) + ": must be > 0";
    return false;
  }
  if (num_taus < 3) {
    if (error) *error = "NoisePsdOptions::num_taus = " + std::to_string(num_taus) + ": must be >= 3";
    return false;
  }
  return true;
}

namespace {
constexpr double kMaxNoiseValue = 1e40;
}  // namespace

Result<NoisePsd> FitNoisePsd(std::span<const double> x, double fs_hz, const NoisePsdOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (!(fs_hz > 0.0) || !std::isfinite(fs_hz)) return InvalidArgument("FitNoisePsd: fs_hz = " + FormatNumber(fs_hz, 4) + ": must be > 0");
  const std::size_t n = x.size();
  if (n < 8) return InvalidInput("FitNoisePsd: " + std::to_string(n) + " samples: need at least 8");
  std::vector<double> c(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(x[i])) return InvalidInput("FitNoisePsd: non-finite value at sample " + std::to_string(i));
    // The coefficients are in x^2 units and a model file holds at most 1e100 (model_file_reader.h);
    // beyond kMaxNoiseValue their products overflowed to inf (found by fuzz_numeric_drift).
    if (!(std::abs(x[i]) <= kMaxNoiseValue)) {
      return InvalidInput("FitNoisePsd: value " + FormatNumber(x[i], 4) + " at sample " + std::to_string(i) +
                          ": beyond 1e40 the noise coefficients (squared units) leave the range a model holds");
    }
    c[i + 1] = c[i] + x[i];
  }
  // Log-spaced averaging factors m_min .. max_tau_fraction * n (at most n / 2: two adjacent means).
  const double m_max = std::max(1.0, std::min(options.max_tau_fraction * static_cast<double>(n), n / 2.0));
  const double m_min = std::clamp(options.min_tau_s.value_or(1.0 / fs_hz) * fs_hz, 1.0, m_max);
  if (m_max < 4.0 * m_min)
    return InvalidInput("FitNoisePsd: " + std::to_string(n) + " samples span too few averaging times (from " +
                        FormatNumber(m_min / fs_hz, 4) + " s to " + FormatNumber(m_max / fs_hz, 4) + " s; need a factor of 4)");
  std::vector<std::size_t> ms;
  for (int k = 0; k < options.num_taus; ++k) {
    const double m = m_min * std::pow(m_max / m_min, static_cast<double>(k) / (options.num_taus - 1));
    const auto mi = static_cast<std::size_t>(std::llround(m));
    if (ms.empty() || mi != ms.back()) ms.push_back(mi);
  }
  // The three Eq. G-1 terms at each tau, and the measured AVAR.
  const auto rows = static_cast<Eigen::Index>(ms.size());
  Eigen::MatrixXd terms(rows, 3);
  Eigen::VectorXd avar(rows), edf(rows), scale(rows);
  for (Eigen::Index r = 0; r < rows; ++r) {
    const auto m = ms[static_cast<std::size_t>(r)];
    const double tau = static_cast<double>(m) / fs_hz;
    avar(r) = OverlappingAvar(c, m);
    if (!(avar(r) > 0.0)) return InvalidInput("FitNoisePsd: the series is constant (Allan variance 0 at tau " + FormatNumber(tau, 4) + " s)");
    terms(r, 0) = ModelAllanVariance({1.0, 0.0, 0.0}, tau);  // Eq. G-1, white
    terms(r, 1) = ModelAllanVariance({0.0, 1.0, 0.0}, tau);  // flicker
    terms(r, 2) = ModelAllanVariance({0.0, 0.0, 1.0}, tau);  // random walk
    edf(r) = static_cast<double>(n) / static_cast<double>(m);  // ~ independent averages
  }
  // Weighted least squares on relative errors: Var(AVAR estimate) ~ 2 AVAR^2 / EDF, so weight
  // EDF / AVAR^2, with AVAR the model's (iterated from the measured one: weights from the data
  // themselves bias a relative fit low by ~1/EDF at the long taus).
  scale = avar;
  NoisePsd best;
  for (int iteration = 0; iteration < kWeightIterations; ++iteration) {
    const Eigen::VectorXd w = (edf.array().sqrt() / scale.array()).matrix();
    const Eigen::MatrixXd a = w.asDiagonal() * terms;
    const Eigen::VectorXd b = w.cwiseProduct(avar);
    auto h = NonNegativeLeastSquares3(a, b);
    if (!h) return InvalidInput("FitNoisePsd: no non-negative noise model fits the Allan variance");
    best = *h;
    scale = terms * Eigen::Vector3d(best.h0, best.h_1, best.h_2);
  }
  return best;
}

double ModelAllanVariance(const NoisePsd& psd, double tau_s) {
  return psd.h0 / (2.0 * tau_s) + 2.0 * kLn2 * psd.h_1 + 2.0 * kPi * kPi / 3.0 * psd.h_2 * tau_s;
}

double RedSpectrumFloorHz(const NoisePsdOptions& options, double duration_s) {
  return 1.0 / (2.0 * std::numbers::pi * options.max_tau_fraction * duration_s);
}

std::vector<double> BlockMeanAutocovariance(const NoisePsd& psd, std::size_t n, double block_s, double f_floor_hz) {
  std::vector<double> r(n, 0.0);
  if (n == 0) return r;
  const std::size_t m = 2 * n;  // circulant grid
  const double df = 1.0 / (static_cast<double>(m) * block_s);
  // Eq. G-2: the red part of the spectrum through the block mean (|H|^2 = sinc^2), sampled once
  // per block: the power at f + a / block_s (a = +-1, +-2, ...) aliases onto f, j = 1 .. n.
  std::vector<double> s(n + 1, 0.0);
  for (std::size_t j = 1; j <= n; ++j) {
    const double f0 = static_cast<double>(j) * df;
    const double sin_x = std::sin(kPi * f0 * block_s);  // the same for every alias, up to sign
    double folded = 0.0;
    for (int a = -kAliases; a <= kAliases; ++a) {
      const double f = std::abs(f0 + a / block_s);
      const double x = kPi * f * block_s;
      const double fr = std::max(f, f_floor_hz);  // = f when there is no floor
      folded += (psd.h_1 / fr + psd.h_2 / (fr * fr)) * sin_x * sin_x / (x * x);
    }
    s[j] = folded * df * (j == n ? 0.5 : 1.0);
  }
  // cos(2 pi j k / m) from a table indexed by (j k) mod m.
  std::vector<double> cos_table(m);
  for (std::size_t i = 0; i < m; ++i) cos_table[i] = std::cos(2.0 * kPi * static_cast<double>(i) / static_cast<double>(m));
  for (std::size_t k = 0; k < n; ++k) {
    double sum = 0.0;
    std::size_t phase = 0;
    for (std::size_t j = 1; j <= n; ++j) {
      phase = (phase + k) % m;
      sum += s[j] * cos_table[phase];
    }
    r[k] = sum;
  }
  r[0] += psd.h0 / (2.0 * block_s);  // white: variance (h0 fs / 2) over block_s fs samples
  return r;
}

}  // namespace gyrocomp
