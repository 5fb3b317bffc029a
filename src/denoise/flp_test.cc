// FLP (Eqs. 14-16): closed-form steps, AR(2) convergence, scale invariance, streaming = batch,
// causality, long-run stability.
#include "gyrocomp/denoise/flp.h"
#include "denoise_numeric_edges.h"

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace gyrocomp {
namespace {

TEST(Flp, FirstTwoStepsByHand) {
  // Order 1, zero initial weights, x = [1, 2]:
  //  n=0: history prefilled with 1, P = 1; xhat = 0, e = 1, eta = beta (1 - exp(-alpha)),
  //       c1 = eta * 1 * 1 / (reg * 1 * 1 + 1).
  //  n=1: xhat = c1 * 1.
  FlpOptions o;
  o.order = 1;
  o.initial_weights = FlpInitialWeights::kZero;
  o.beta = 0.5;
  o.alpha = 2.0;
  o.power_forgetting = 0.9;
  o.regularization = 0.0;
  auto f = FlpFilter::Create(o);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->Process(1.0), 0.0);
  const double eta0 = 0.5 * (1.0 - std::exp(-2.0));
  EXPECT_DOUBLE_EQ(f->last_step(), eta0);
  EXPECT_DOUBLE_EQ(f->weights()[0], eta0);
  EXPECT_DOUBLE_EQ(f->Process(2.0), eta0);
  // n=1: e = 2 - eta0, P = 0.9 * 1 + 0.1 * 4 = 1.3, eta = beta (1 - exp(-alpha e^2 / P)),
  //      regressor X = [1], c1 += eta e.
  const double e1 = 2.0 - eta0;
  const double eta1 = 0.5 * (1.0 - std::exp(-2.0 * e1 * e1 / 1.3));
  EXPECT_DOUBLE_EQ(f->power(), 1.3);
  EXPECT_DOUBLE_EQ(f->last_step(), eta1);
  EXPECT_DOUBLE_EQ(f->weights()[0], eta0 + eta1 * e1);
  EXPECT_EQ(f->num_processed(), 2u);
}

TEST(Flp, ConvergesToTheCoefficientsOfAnAr2Process) {
  // x(n) = 1.2 x(n-1) - 0.6 x(n-2) + w(n): the optimal one-step predictor of order 2 is exactly
  // (1.2, -0.6), and LMS converges to it in the mean.
  const double a1 = 1.2, a2 = -0.6;
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> g(0.0, 1.0);
  const std::size_t n = 200000;
  std::vector<double> x(n, 0.0);
  for (std::size_t i = 2; i < n; ++i) x[i] = a1 * x[i - 1] + a2 * x[i - 2] + g(rng);
  FlpOptions o;
  o.order = 2;
  o.initial_weights = FlpInitialWeights::kZero;
  o.beta = 0.02;
  o.alpha = 50.0;  // step close to beta except for tiny errors
  auto f = FlpFilter::Create(o);
  ASSERT_TRUE(f.ok());
  double c1 = 0.0, c2 = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    f->Process(x[i]);
    if (i >= n / 2) {  // average the weights over the second half (LMS jitters around the optimum)
      c1 += f->weights()[0];
      c2 += f->weights()[1];
      ++count;
    }
  }
  c1 /= static_cast<double>(count);
  c2 /= static_cast<double>(count);
  // NLMS with step 0.02: misadjustment ~1%, weight jitter ~0.01 RMS; the 100k-sample average is
  // within a few 1e-3 of the optimum. 0.02 leaves margin and still rejects a wrong update sign or
  // normalisation (which would not converge at all).
  EXPECT_NEAR(c1, a1, 0.02);
  EXPECT_NEAR(c2, a2, 0.02);
}

std::vector<double> NoisyRamp(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = 0.5 + 1e-4 * static_cast<double>(i) + std::sin(0.01 * i) + 0.3 * g(rng);
  return x;
}

TEST(Flp, OutputScalesWithInput) {
  const std::vector<double> x = NoisyRamp(20000, 5);
  for (double k : {1e6, 1e-6, -3.0}) {
    std::vector<double> xs(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) xs[i] = k * x[i];
    const auto y = FlpDenoise(x, {});
    const auto ys = FlpDenoise(xs, {});
    ASSERT_TRUE(y.ok() && ys.ok());
    double worst = 0.0, scale = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      worst = std::max(worst, std::abs((*ys)[i] - k * (*y)[i]));
      scale = std::max(scale, std::abs(k * (*y)[i]));
    }
    // Every quantity of the update is homogeneous in the input (NLMS, e^2/P, eps ~ P), so the
    // results differ only by rounding, which the stable adaptation does not amplify: 1e-10
    // relative (measured ~1e-14).
    EXPECT_LT(worst, 1e-10 * scale) << "k = " << k;
  }
}

TEST(Flp, StreamingEqualsBatchAndIsCausal) {
  const std::vector<double> x = NoisyRamp(5000, 9);
  const auto batch = RunFlp(x, {});
  ASSERT_TRUE(batch.ok());
  auto f = FlpFilter::Create({});
  ASSERT_TRUE(f.ok());
  for (std::size_t i = 0; i < x.size(); ++i) ASSERT_EQ(f->Process(x[i]), batch->filtered[i]) << i;
  // Changing the future does not change the past.
  std::vector<double> y = x;
  for (std::size_t i = 3000; i < y.size(); ++i) y[i] += 100.0;
  const auto other = RunFlp(y, {});
  ASSERT_TRUE(other.ok());
  for (std::size_t i = 0; i <= 3000; ++i) ASSERT_EQ(other->filtered[i], batch->filtered[i]) << i;
  // Reset restarts exactly.
  f->Reset();
  EXPECT_EQ(f->Process(x[0]), batch->filtered[0]);
}

TEST(Flp, ConstantInputPassesUnchanged) {
  // Moving-average start, constant input: the prediction is the constant and the error 0, so the
  // weights never move.
  const std::vector<double> x(1000, 0.25);
  const auto r = RunFlp(x, {});
  ASSERT_TRUE(r.ok());
  for (double v : r->filtered) EXPECT_DOUBLE_EQ(v, 0.25);
  const auto zeros = RunFlp(std::vector<double>(100, 0.0), {});
  ASSERT_TRUE(zeros.ok());
  for (double v : zeros->filtered) EXPECT_EQ(v, 0.0);
}

TEST(Flp, ReducesWhiteNoiseOnASlowSignal) {
  const std::vector<double> x = NoisyRamp(50000, 3);
  std::vector<double> truth(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) truth[i] = 0.5 + 1e-4 * static_cast<double>(i) + std::sin(0.01 * i);
  const auto r = RunFlp(x, {});
  ASSERT_TRUE(r.ok());
  double raw = 0.0, out = 0.0;
  for (std::size_t i = 1000; i < x.size(); ++i) {
    raw += (x[i] - truth[i]) * (x[i] - truth[i]);
    out += (r->filtered[i] - truth[i]) * (r->filtered[i] - truth[i]);
  }
  // An 8-tap predictor averages ~8 past samples: noise power / ~8 minus its lag error on a
  // 0.01 rad/sample sine; requiring a factor 2 in RMS is conservative.
  EXPECT_LT(std::sqrt(out), std::sqrt(raw) / 2.0);
}

TEST(Flp, StableOverFiveMillionSamples) {
  // A long record with a bias, a slow random walk and white noise, plus a few outliers: the
  // weights stay bounded and the output finite (NLMS with beta < 2 cannot diverge).
  std::mt19937_64 rng(77);
  std::normal_distribution<double> g(0.0, 1.0);
  auto f = FlpFilter::Create({});
  ASSERT_TRUE(f.ok());
  double walk = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < 5000000; ++i) {
    walk += 1e-3 * g(rng);
    double x = 0.1 + walk + 0.05 * g(rng);
    if (i % 1000003 == 999) x += 50.0;  // rare spikes
    const double y = f->Process(x);
    ASSERT_TRUE(std::isfinite(y)) << i;
    worst = std::max(worst, std::abs(y - x));
  }
  double norm = 0.0;
  for (double c : f->weights()) norm += std::abs(c);
  EXPECT_LT(norm, 10.0);
  EXPECT_LT(worst, 100.0);
}

TEST(Flp, InvalidOptionsAndInputs) {
  std::string why;
  FlpOptions o;
  o.beta = 3.0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_EQ(why, "FlpOptions::beta = 3: must be in (0, 2) (NLMS stability)");
  o = {};
  o.order = 0;
  EXPECT_FALSE(FlpFilter::Create(o).ok());
  o = {};
  o.alpha = -1.0;
  EXPECT_EQ(RunFlp(std::vector<double>{1.0}, o).error().kind, ErrorKind::kInvalidArgument);
  o = {};
  o.power_forgetting = 1.0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_EQ(RunFlp(std::vector<double>{}, {}).error().kind, ErrorKind::kInvalidInput);
  const auto inf = RunFlp(std::vector<double>{1.0, INFINITY}, {});
  ASSERT_FALSE(inf.ok());
  EXPECT_NE(inf.error().message.find("sample 1"), std::string::npos);
  EXPECT_EQ(*ParseFlpInitialWeights("zero"), FlpInitialWeights::kZero);
}

// Near the ends of the double range (fuzz_numeric_stages): see denoise_numeric_edges.h.
TEST(NumericEdges, FlpDenoiseNearTheEndsOfTheDoubleRange) {
  testing::ExpectDenoiseScaleFreeNearTheEndsOfTheDoubleRange(
      [](const std::vector<double>& x) { return FlpDenoise(x, FlpOptions{}); });
}

}  // namespace
}  // namespace gyrocomp
