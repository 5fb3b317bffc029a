// Bandwidth measurement against processings whose response is known in closed form.
#include "gyrocomp/denoise/bandwidth.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

namespace gyrocomp {
namespace {

SignalProcessing Delay(std::size_t d) {
  return [d](std::span<const double> x) -> Result<std::vector<double>> {
    std::vector<double> y(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) y[i] = x[i >= d ? i - d : 0];
    return y;
  };
}

SignalProcessing MovingAverage(std::size_t m) {
  return [m](std::span<const double> x) -> Result<std::vector<double>> {
    std::vector<double> y(x.size());
    double s = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      s += x[i];
      if (i >= m) s -= x[i - m];
      y[i] = s / static_cast<double>(std::min(i + 1, m));
    }
    return y;
  };
}

TEST(Bandwidth, IdentityAndPureDelay) {
  BandwidthOptions o;
  o.fs_hz = 100.0;
  o.num_samples = 1 << 14;
  o.white_noise_sd = 1.0;
  const auto id = MeasureBandwidth(Delay(0), {}, o);
  ASSERT_TRUE(id.ok()) << id.error().message;
  EXPECT_FALSE(id->bandwidth_hz.has_value());
  for (double g : id->gain) EXPECT_NEAR(g, 1.0, 1e-9);
  EXPECT_NEAR(id->delay_s, 0.0, 1e-9);
  EXPECT_EQ(id->num_runs, id->frequency_hz.size() + 1);
  const auto d = MeasureBandwidth(Delay(7), {}, o);
  ASSERT_TRUE(d.ok());
  // A delay of 7 samples at 100 Hz: 0.07 s; gain exactly 1 inside the window.
  EXPECT_NEAR(d->delay_s, 0.07, 1e-9);
  for (double g : d->gain) EXPECT_NEAR(g, 1.0, 1e-9);
}

TEST(Bandwidth, MovingAverageMatchesItsTransferFunction) {
  // |H(f)| = |sin(pi f M / fs) / (M sin(pi f / fs))|, delay (M - 1) / 2 samples.
  const std::size_t m = 16;
  const double fs = 100.0;
  auto gain = [&](double f) {
    return std::abs(std::sin(std::numbers::pi * f * m / fs) / (m * std::sin(std::numbers::pi * f / fs)));
  };
  double lo = 0.01, hi = fs / m;  // gain(lo) > -3 dB > gain(hi = first zero)
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (gain(mid) > 1.0 / std::sqrt(2.0) ? lo : hi) = mid;
  }
  BandwidthOptions o;
  o.fs_hz = fs;
  o.num_samples = 1 << 14;
  o.num_frequencies = 64;
  o.white_noise_sd = 1.0;
  const auto r = MeasureBandwidth(MovingAverage(m), {}, o);
  ASSERT_TRUE(r.ok());
  for (std::size_t k = 0; k < r->frequency_hz.size(); ++k) {
    EXPECT_NEAR(r->gain[k], gain(r->frequency_hz[k]), 1e-9) << r->frequency_hz[k];  // linear: exact
  }
  ASSERT_TRUE(r->bandwidth_hz.has_value());
  // The crossing is interpolated between test tones ~10% apart in frequency, on a smooth curve:
  // 1% is several times the measured interpolation error.
  EXPECT_NEAR(*r->bandwidth_hz, lo, 0.01 * lo);
  EXPECT_NEAR(r->delay_s, (m - 1) / 2.0 / fs, 1e-6);
}

TEST(Bandwidth, NarrowFilterIsBelowRangeAndErrorsPassThrough) {
  BandwidthOptions o;
  o.fs_hz = 1.0;
  o.white_noise_sd = 1.0;
  o.min_frequency_hz = 0.2;
  o.max_frequency_hz = 0.4;
  const auto r = MeasureBandwidth(MovingAverage(64), {}, o);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->bandwidth_below_range);
  SignalProcessing failing = [](std::span<const double>) -> Result<std::vector<double>> {
    return InvalidInput("nope");
  };
  EXPECT_EQ(MeasureBandwidth(failing, {}, o).error().message, "nope");
  SignalProcessing shortening = [](std::span<const double> x) -> Result<std::vector<double>> {
    return std::vector<double>(x.size() - 1, 0.0);
  };
  EXPECT_EQ(MeasureBandwidth(shortening, {}, o).error().kind, ErrorKind::kInternal);
  BandwidthOptions bad;
  bad.fs_hz = 0.0;
  std::string why;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_EQ(why.rfind("BandwidthOptions::fs_hz", 0), 0u);
  EXPECT_EQ(MeasureBandwidth(Delay(0), std::vector<double>(100, 0.0), {}).error().kind,
            ErrorKind::kInvalidArgument);  // too short for a window
}

}  // namespace
}  // namespace gyrocomp
