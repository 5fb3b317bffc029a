#include "gyrocomp/drift/temperature_rate.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace gyrocomp {
namespace {

// A straight line is fitted exactly by every window, truncated or not: the slope is exact to
// rounding. Bound 1e-12 relative: the rounding of the long-double running sums gives about
// 4 eps_ld (n / W)^3 = 4 * 1.1e-19 * 13.3^3 = 1e-15 here (double sums gave 1.0e-12: the test
// caught that and the sums became long double).
TEST(TemperatureRate, KnownRampIsExactEverywhere) {
  const double fs_hz = 5.0;
  const double slope_c_per_s = -1.0 / 60.0;  // -1 C/min, a chamber ramp
  std::vector<double> t(20000);
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = 60.0 + slope_c_per_s * static_cast<double>(i) / fs_hz;
  auto r = TemperatureRate(t, fs_hz);
  ASSERT_TRUE(r.ok());
  for (std::size_t i = 0; i < t.size(); ++i)
    ASSERT_NEAR((*r)[i], slope_c_per_s, 1e-12 * std::abs(slope_c_per_s)) << "sample " << i;
}

// A centred window differentiates a parabola exactly (the quadratic term is symmetric about the
// centre); truncated windows at the ends are not centred and are excluded.
TEST(TemperatureRate, ParabolaExactInTheInterior) {
  const double fs_hz = 2.0;
  TemperatureRateOptions o;
  o.window_s = 100.0;  // 201 samples
  std::vector<double> t(5000);
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double ts = static_cast<double>(i) / fs_hz;
    t[i] = 20.0 + 1e-3 * ts + 2e-7 * ts * ts;
  }
  auto r = TemperatureRate(t, fs_hz, o);
  ASSERT_TRUE(r.ok());
  for (std::size_t i = 100; i + 100 < t.size(); ++i) {
    const double ts = static_cast<double>(i) / fs_hz;
    // 1e-10 C/s absolute: rounding of sums of up to 201 values of ~25 C.
    ASSERT_NEAR((*r)[i], 1e-3 + 4e-7 * ts, 1e-10) << "sample " << i;
  }
}

// Noisy, quantized sensor: the error of the slope matches the least-squares theory
// sd = s * fs * sqrt(12 / (W (W^2 - 1))) with s^2 = noise^2 + q^2 / 12 (W samples per window),
// while a plain finite difference is hundreds of times worse. The RMS error over 2e5 samples
// (~66 independent windows: relative standard error ~9%) is checked within a factor 1.3 (3 SE).
TEST(TemperatureRate, NoisyQuantizedRampMatchesTheory) {
  const double fs_hz = 10.0;
  const double q_c = 0.0625;       // a 12-bit digital temperature sensor LSB
  const double noise_c = 0.02;
  const double slope = 0.5 / 60.0;  // 0.5 C/min
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, noise_c);
  std::vector<double> t(200000);
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double truth = -20.0 + slope * static_cast<double>(i) / fs_hz;
    t[i] = q_c * std::round((truth + n(rng)) / q_c);
  }
  TemperatureRateOptions o;  // default 300 s window = 3001 samples
  auto r = TemperatureRate(t, fs_hz, o);
  ASSERT_TRUE(r.ok());
  const double w = 3001.0;
  const double s = std::sqrt(noise_c * noise_c + q_c * q_c / 12.0);
  const double theory = s * fs_hz * std::sqrt(12.0 / (w * (w * w - 1.0)));
  double ss = 0.0, ss_fd = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 1500; i + 1500 < t.size(); ++i) {
    ss += ((*r)[i] - slope) * ((*r)[i] - slope);
    const double fd = (t[i + 1] - t[i]) * fs_hz;
    ss_fd += (fd - slope) * (fd - slope);
    ++count;
  }
  const double rms = std::sqrt(ss / count);
  EXPECT_LT(rms, 1.3 * theory);
  EXPECT_GT(rms, theory / 1.3);
  EXPECT_GT(std::sqrt(ss_fd / count), 100.0 * rms);
}

TEST(TemperatureRate, ShortRecordsAndErrors) {
  auto r = TemperatureRate(std::vector<double>{1.0, 2.0}, 1.0);
  ASSERT_TRUE(r.ok());
  EXPECT_DOUBLE_EQ((*r)[0], 1.0);
  EXPECT_DOUBLE_EQ((*r)[1], 1.0);
  EXPECT_FALSE(TemperatureRate(std::vector<double>{1.0}, 1.0).ok());
  EXPECT_FALSE(TemperatureRate(std::vector<double>{1.0, 2.0}, 0.0).ok());
  auto bad = TemperatureRate(std::vector<double>{1.0, std::nan(""), 3.0}, 1.0);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().kind, ErrorKind::kInvalidInput);
  TemperatureRateOptions o;
  o.window_s = -1.0;
  auto e = TemperatureRate(std::vector<double>{1.0, 2.0}, 1.0, o);
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().message, "TemperatureRateOptions::window_s = -1: must be > 0");
}

}  // namespace
}  // namespace gyrocomp
