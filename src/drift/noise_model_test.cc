// The noise model of the polynomial fit (noise_model.h): Allan-variance fit (Eq. G-1), block-mean
// covariance (Eq. G-2) against closed forms, and GLS (Eq. G-3) against OLS on correlated noise.
#include "gyrocomp/drift/noise_model.h"

#include <cmath>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/sim/simulator.h"

namespace gyrocomp {
namespace {

constexpr double kPi = std::numbers::pi;

// White noise of standard deviation sigma plus a random walk of K per sqrt(s), at fs_hz.
std::vector<double> WhitePlusRandomWalk(std::size_t n, double fs_hz, double sigma, double k, unsigned seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(n);
  double walk = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    walk += k / std::sqrt(fs_hz) * g(gen);
    x[i] = sigma * g(gen) + walk;
  }
  return x;
}

// Closed form: white noise of variance sigma^2 at fs has h0 = 2 sigma^2 / fs (one-sided), no
// flicker, no random walk. 200 000 samples: the AVAR at short taus is known to ~0.3%, so 3% on
// h0 leaves room for the long-tau points (few averages) without hiding a factor error.
TEST(NoisePsd, WhiteNoiseGivesH0) {
  const double fs_hz = 10.0, sigma = 0.02;
  const std::vector<double> x = WhitePlusRandomWalk(200000, fs_hz, sigma, 0.0, 1);
  auto psd = FitNoisePsd(x, fs_hz);
  ASSERT_TRUE(psd.ok()) << psd.error().message;
  EXPECT_NEAR(psd->h0, 2.0 * sigma * sigma / fs_hz, 0.03 * 2.0 * sigma * sigma / fs_hz);
  // What flicker / random walk the fit finds must stay below 5% of the white AVAR at the
  // longest tau fitted (record / 10 = 2000 s): AVAR_white(2000 s) = h0 / 4000.
  const double white_long = psd->h0 / 4000.0;
  EXPECT_LT(2.0 * std::log(2.0) * psd->h_1, 0.05 * white_long);
  EXPECT_LT(2.0 * kPi * kPi / 3.0 * psd->h_2 * 2000.0, 0.05 * white_long);
  // ARW in datasheet units: sigma sqrt(1 / fs) deg/sqrt(s) = 60x that in deg/sqrt(h).
  EXPECT_NEAR(psd->arw_deg_per_sqrt_h(), 60.0 * sigma / std::sqrt(fs_hz), 0.02 * 60.0 * sigma / std::sqrt(fs_hz));
}

// White + random walk: K from the AVAR's +1/2 slope (K^2 = 2 pi^2 h_2). The long-tau AVAR points
// carry ~10-20 independent averages each; over 3 seeds the recovered K must be within 15%.
TEST(NoisePsd, RandomWalkRecovered) {
  const double fs_hz = 1.0, sigma = 0.01, k = 2e-4;
  for (unsigned seed : {1u, 2u, 3u}) {
    const std::vector<double> x = WhitePlusRandomWalk(100000, fs_hz, sigma, k, seed);
    auto psd = FitNoisePsd(x, fs_hz);
    ASSERT_TRUE(psd.ok()) << psd.error().message;
    EXPECT_NEAR(kPi * std::sqrt(2.0 * psd->h_2), k, 0.15 * k) << "seed " << seed;
    EXPECT_NEAR(psd->h0, 2.0 * sigma * sigma / fs_hz, 0.05 * 2.0 * sigma * sigma / fs_hz) << "seed " << seed;
  }
}

// Simulator round trip: the simulator's noise (ARW 1.667 deg/sqrt(h), bias instability 44 deg/h
// as Gauss-Markov processes 10 .. 1e5 s, RRW 3 deg/h/sqrt(h)), 14.25 h at 1 Hz, fitted from 60 s
// (as the drift fit's GLS does) to record / 10. The simulator's flicker floor is flat within 2%
// from 200 s (include/gyrocomp/sim/simulator.h) and the AVAR estimates at the long taus have
// ~10-50 independent averages: B within 15% on 3 seeds.
TEST(NoisePsd, SimulatorBiasInstabilityRecovered) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    SimulatorOptions o;
    o.fs_hz = 1.0;
    o.seed = seed;
    o.duration_s = 14.25 * 3600.0;
    auto run = Simulate(o);
    ASSERT_TRUE(run.ok()) << run.error().message;
    NoisePsdOptions po;
    po.min_tau_s = 60.0;
    auto psd = FitNoisePsd(run->true_noise_dps, o.fs_hz, po);
    ASSERT_TRUE(psd.ok()) << psd.error().message;
    EXPECT_NEAR(psd->bias_instability_deg_per_h(), 44.0, 0.15 * 44.0) << "seed " << seed;
  }
}

TEST(NoisePsd, BadInputIsAnError) {
  EXPECT_FALSE(FitNoisePsd(std::vector<double>(100, 1.0), 1.0).ok());  // constant
  EXPECT_FALSE(FitNoisePsd(std::vector<double>(5, 0.1), 1.0).ok());    // too short
  std::vector<double> x = WhitePlusRandomWalk(100, 1.0, 1.0, 0.0, 1);
  x[50] = std::nan("");
  EXPECT_FALSE(FitNoisePsd(x, 1.0).ok());
  EXPECT_FALSE(FitNoisePsd(WhitePlusRandomWalk(100, 1.0, 1.0, 0.0, 1), 0.0).ok());
  NoisePsdOptions bad;
  bad.max_tau_fraction = 0.0;
  EXPECT_FALSE(FitNoisePsd(WhitePlusRandomWalk(100, 1.0, 1.0, 0.0, 1), 1.0, bad).ok());
}

// Eq. G-2 against closed forms. White: h0 / (2 P) at lag 0, nothing elsewhere. Random walk of
// K^2 = 2 pi^2 h_2: block means of a Wiener process have the structure function
// E (m_i - m_{i+k})^2 = 2 (R(0) - R(k)) = K^2 P (k - 1/3) for k >= 1. Flicker: the Allan variance
// at tau = P is R(0) - R(1) = 2 ln2 h_1. Tolerances: the circulant grid cuts the spectrum below
// 1 / (2 record) (2 000 blocks here: that removes a near-constant, which the differences do not
// see, plus a curvature of order k^2 / n^2); the flicker one is 3% (the 1/f integral's
// discretisation near the cut, measured 1.2%).
TEST(BlockMeanAutocovariance, ClosedForms) {
  const std::size_t n = 2000;
  const double p = 60.0;
  const std::vector<double> white = BlockMeanAutocovariance({2e-3, 0.0, 0.0}, n, p);
  EXPECT_DOUBLE_EQ(white[0], 2e-3 / (2.0 * p));
  for (std::size_t k = 1; k < n; ++k) ASSERT_EQ(white[k], 0.0) << k;
  const double h2 = 1e-10, k2 = 2.0 * kPi * kPi * h2;
  const std::vector<double> rw = BlockMeanAutocovariance({0.0, 0.0, h2}, n, p);
  for (std::size_t k : {1u, 2u, 5u, 10u, 20u}) {
    const double expected = k2 * p * (static_cast<double>(k) - 1.0 / 3.0);
    EXPECT_NEAR(2.0 * (rw[0] - rw[k]), expected, 0.02 * expected) << "lag " << k;
  }
  const double h1 = 5e-5;
  const std::vector<double> flicker = BlockMeanAutocovariance({0.0, h1, 0.0}, n, p);
  EXPECT_NEAR(flicker[0] - flicker[1], 2.0 * std::log(2.0) * h1, 0.03 * 2.0 * std::log(2.0) * h1);
}

// A cooling-and-heating profile 60 -> -35 -> 60 C twice over 8 h at 1 Hz, and a cubic drift.
std::vector<double> Profile() {
  const std::size_t n = 8 * 3600;
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double u = std::fmod(2.0 * static_cast<double>(i) / static_cast<double>(n), 1.0);
    t[i] = 60.0 - 95.0 * (u < 0.5 ? 2.0 * u : 2.0 - 2.0 * u);
  }
  return t;
}
double Drift(double t) { return 0.01 - 1e-3 * t + 3e-5 * t * t + 1e-7 * t * t * t; }

// Eq. G-3: on white + random-walk noise (correlated over hours, like a gyro's bias wander) GLS
// with the fitted noise model recovers the drift polynomial better than OLS. Error: mean square
// over a grid of -35..60 C of (fitted - true drift), over 48 seeds. Expected size (Gauss-Markov,
// exact covariance of a walk started at 0, 60 s blocks): 0.31x, of which the constant is most;
// the shape alone 0.95x. The stationary Eq. G-2 model cannot know where the walk started, so the
// gain is between. Asserted: < 0.93x and GLS better on at least 31 of 48 seeds (if GLS were no
// better than OLS, 31 or more would happen 3% of the time). Measured: 0.88x, 35 of 48.
// The polynomial model fitted to (temp, y) at 1 Hz by ordinary least squares and by GLS with the
// Allan noise model.
auto FitOlsAndGls(const std::vector<double>& temp, const std::vector<double>& y) {
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  auto ols = FitDriftModel({temp, 1.0}, y, o);
  o.noise_model = DriftNoiseModel::kAllan;
  return std::make_pair(std::move(ols), FitDriftModel({temp, 1.0}, y, o));
}

TEST(DriftModelGls, RecoversCoefficientsBetterThanOlsOnCorrelatedNoise) {
  const std::vector<double> temp = Profile();
  std::vector<double> grid;
  for (double t = -35.0; t <= 60.0; t += 1.0) grid.push_back(t);
  double ss_ols = 0.0, ss_gls = 0.0;
  int gls_better = 0;
  const int seeds = 48;
  for (int seed = 1; seed <= seeds; ++seed) {
    std::vector<double> y = WhitePlusRandomWalk(temp.size(), 1.0, 0.02, 2e-4, static_cast<unsigned>(seed));
    for (std::size_t i = 0; i < y.size(); ++i) y[i] += Drift(temp[i]);
    auto [ols, gls] = FitOlsAndGls(temp, y);
    ASSERT_TRUE(ols.ok() && gls.ok()) << (gls.ok() ? ols.error().message : gls.error().message);
    ASSERT_TRUE(gls->summary.noise_psd.has_value());
    EXPECT_EQ(gls->summary.noise_model, DriftNoiseModel::kAllan);
    EXPECT_EQ(gls->summary.train_period_s, 60.0);
    double e_ols = 0.0, e_gls = 0.0;
    for (double t : grid) {
      e_ols += std::pow(ols->structured->PredictOne(t, 0.0) - Drift(t), 2) / static_cast<double>(grid.size());
      e_gls += std::pow(gls->structured->PredictOne(t, 0.0) - Drift(t), 2) / static_cast<double>(grid.size());
    }
    ss_ols += e_ols;
    ss_gls += e_gls;
    gls_better += e_gls < e_ols;
  }
  const double ratio = std::sqrt(ss_gls / ss_ols);
  std::printf("GLS / OLS RMS error over %d seeds: %.3f (GLS better on %d)\n", seeds, ratio, gls_better);
  EXPECT_LT(ratio, 0.93);
  EXPECT_GE(gls_better, 31);
}

// On white noise there is nothing to re-weight: GLS on 60 s block means is OLS on block means,
// within a small fraction of OLS's own error of the full-rate fit.
TEST(DriftModelGls, EqualsOlsOnWhiteNoise) {
  const std::vector<double> temp = Profile();
  std::vector<double> y = WhitePlusRandomWalk(temp.size(), 1.0, 0.02, 0.0, 7);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] += Drift(temp[i]);
  auto [ols, gls] = FitOlsAndGls(temp, y);
  ASSERT_TRUE(ols.ok() && gls.ok());
  double d = 0.0, e = 0.0;
  for (double t = -35.0; t <= 60.0; t += 1.0) {
    d += std::pow(gls->structured->PredictOne(t, 0.0) - ols->structured->PredictOne(t, 0.0), 2);
    e += std::pow(ols->structured->PredictOne(t, 0.0) - Drift(t), 2);
  }
  EXPECT_LT(std::sqrt(d), 0.25 * std::sqrt(e));
  // The flicker found is small against the white AVAR at the block period (60 s).
  EXPECT_LT(gls->summary.noise_psd->h_1 * 2.0 * std::log(2.0), 0.05 * gls->summary.noise_psd->h0 / 2.0 / 60.0);
}

TEST(DriftModelGls, OnlyForThePolynomial) {
  DriftFitOptions o;
  o.noise_model = DriftNoiseModel::kAllan;
  std::string why;
  o.model = DriftModelKind::kAuto;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("poly only"), std::string::npos) << why;
  o.model = DriftModelKind::kCsSvr;
  EXPECT_FALSE(o.IsValid(&why));
  o.model = DriftModelKind::kPolynomial;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o.gls_block_s = 0.0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_EQ(ParseDriftNoiseModel("allan"), DriftNoiseModel::kAllan);
  EXPECT_EQ(ParseDriftNoiseModel("white"), DriftNoiseModel::kWhite);
  EXPECT_FALSE(ParseDriftNoiseModel("gls").has_value());
}

}  // namespace
}  // namespace gyrocomp
