// The pooled cubic (pooled_fit.h) on its own: one shared curve with a constant per group, its
// curve_sd against the actual error under slow noise (Eqs. P-1, P-2), and the rate term admitted
// only when its held-out gain beats its standard error.
#include <cmath>
#include <cstddef>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/calibrate/pooled_fit.h"
#include "gyrocomp/sim/simulator.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

TEST(PooledCubic, ConstantsPerGroupAndOneSharedCurve) {
  // Three groups on overlapping ranges, each with its own constant: the curve comes back.
  std::vector<double> t, y;
  std::vector<std::size_t> g;
  NormalGenerator rng(5);
  const double b[3] = {0.3, -0.2, 0.05};
  for (std::size_t grp = 0; grp < 3; ++grp)
    for (int i = 0; i < 200; ++i) {
      const double temp = 5.0 + 10.0 * static_cast<double>(grp) + 0.1 * i, d = temp - 25.0;
      t.push_back(temp), g.push_back(grp);
      y.push_back(b[grp] + 0.01 * d - 3e-4 * d * d + 2e-6 * d * d * d + 1e-4 * rng.Next());
    }
  Result<PooledCubic> f = FitPooledCubic(t, y, g, 3, 25.0);
  ASSERT_TRUE(f.ok()) << f.error().message;
  EXPECT_NEAR(f->slope[0], 0.01, 1e-4);
  EXPECT_NEAR(f->slope[1], -3e-4, 1e-5);
  EXPECT_NEAR(f->slope[2], 2e-6, 1e-6);
  for (std::size_t grp = 0; grp < 3; ++grp) EXPECT_NEAR(f->group_constant[grp], b[grp], 1e-3);
  EXPECT_GT(f->curve_sd, 0.0);
  // No change inside any group: nothing identified.
  EXPECT_FALSE(FitPooledCubic({10, 10, 10, 10, 20, 20, 20, 20}, {1, 1, 1, 1, 2, 2, 2, 2}, {0, 0, 0, 0, 1, 1, 1, 1}, 2, 15.0).ok());
}

// curve_sd against the actual error of the curve when the rows' noise is slow: AR(1) (phi 0.99 per
// row, a 100-row correlation) and a random walk under white noise, three groups of 600 rows each
// warming 10 -> 60 C with no true curve. Over 100 draws the stated 1 sigma (RMS) is within 1.5x
// of the fitted curve's actual RMS error over the range; the rows taken as independent would
// state under a tenth of the actual error (white noise of the same row variance).
TEST(PooledCubic, CurveSdMatchesTheActualErrorUnderSlowNoise) {
  for (const bool random_walk : {false, true}) {
    NormalGenerator rng(random_walk ? 23 : 17);
    double stated = 0.0, actual = 0.0;
    constexpr int kDraws = 100;
    for (int draw = 0; draw < kDraws; ++draw) {
      std::vector<double> t, y;
      std::vector<std::size_t> g;
      for (std::size_t grp = 0; grp < 3; ++grp) {
        double e = 0.0;
        for (int i = 0; i < 600; ++i) {
          e = random_walk ? e + 0.05 * rng.Next() : 0.99 * e + rng.Next();
          t.push_back(10.0 + 50.0 * i / 599.0 + static_cast<double>(grp)), g.push_back(grp);
          y.push_back(e + (random_walk ? rng.Next() : 0.0));
        }
      }
      Result<PooledCubic> f = FitPooledCubic(t, y, g, 3, 35.0);
      ASSERT_TRUE(f.ok()) << f.error().message;
      // The fitted curve's error: the curve itself (the truth is 0), centred, RMS over 101 temperatures.
      const auto [lo, hi] = std::minmax_element(t.begin(), t.end());
      std::vector<double> c;
      double mean = 0.0, ss = 0.0;
      for (int i = 0; i <= 100; ++i) {
        const double d = *lo + (*hi - *lo) * i / 100.0 - 35.0;
        c.push_back(f->slope[0] * d + f->slope[1] * d * d + f->slope[2] * d * d * d);
        mean += c.back() / 101.0;
      }
      for (double v : c) ss += (v - mean) * (v - mean) / 101.0;
      actual += ss / kDraws;
      stated += f->curve_sd * f->curve_sd / kDraws;
    }
    const double ratio = std::sqrt(stated / actual);
    std::printf("%s: curve_sd %.3g, actual %.3g, ratio %.2f\n", random_walk ? "random walk" : "AR(1)", std::sqrt(stated),
                std::sqrt(actual), ratio);
    EXPECT_GT(ratio, 1.0 / 1.5) << random_walk;
    EXPECT_LT(ratio, 1.5) << random_walk;
  }
}

// The dT/dt term enters the pooled fit as a term enters the default drift model: only when its
// held-out gain (each group left out in turn) beats its standard error. Six warm-ups whose
// heating rate wanders independently of the temperature: with a real gain the term is kept and
// recovered; with none it is tried and left out.
TEST(PooledCubic, RateTermOnlyWhenItsHeldOutGainBeatsItsStandardError) {
  for (const double true_gain : {0.5, 0.0}) {
    std::vector<double> t, y, rate;
    std::vector<std::size_t> g;
    NormalGenerator rng(11);
    for (std::size_t grp = 0; grp < 6; ++grp) {
      double temp = 5.0 + 2.0 * static_cast<double>(grp);
      for (int i = 0; i < 300; ++i) {
        const double r = 0.02 + 0.015 * std::sin(0.05 * i + static_cast<double>(grp));  // C/s
        temp += r * 10.0;  // 10 s rows
        const double d = temp - 25.0;
        t.push_back(temp), rate.push_back(r), g.push_back(grp);
        y.push_back(0.1 * static_cast<double>(grp) + 0.01 * d - 2e-4 * d * d + true_gain * r + 1e-4 * rng.Next());
      }
    }
    Result<PooledCubic> f = FitPooledCubic(t, y, g, 6, 25.0, rate);
    ASSERT_TRUE(f.ok()) << f.error().message;
    EXPECT_EQ(f->rate_term.pairs, 6u) << true_gain;
    EXPECT_EQ(f->rate_used, true_gain > 0.0) << f->rate_term.BriefReport();
    if (true_gain > 0.0) {
      EXPECT_NEAR(f->rate_gain, true_gain, 0.02);
    }
    EXPECT_NEAR(f->slope[0], 0.01, 2e-4) << true_gain;
  }
}

}  // namespace
}  // namespace gyrocomp
