// WFLP: structure (what happens to each band), scale invariance, long-run stability.
#include "gyrocomp/denoise/wflp.h"
#include "gyrocomp/denoise/flp.h"
#include "gyrocomp/denoise/wavelet_denoise.h"
#include "denoise_numeric_edges.h"

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace gyrocomp {
namespace {

struct Record {
  std::vector<double> truth;
  std::vector<double> x;
};

// A gyro-like record: bias, slow sinusoidal motion and a random walk, plus white noise.
Record MakeRecord(std::size_t n, double noise_sd, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Record r;
  r.truth.resize(n);
  r.x.resize(n);
  double walk = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    walk += 2e-4 * g(rng);
    r.truth[i] = 0.2 + 0.3 * std::sin(2e-3 * static_cast<double>(i)) + walk;
    r.x[i] = r.truth[i] + noise_sd * g(rng);
  }
  return r;
}

double Rms(const std::vector<double>& a, const std::vector<double>& b, std::size_t skip = 0) {
  double s = 0.0;
  for (std::size_t i = skip; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s / static_cast<double>(a.size() - skip));
}

TEST(Wflp, ReducesNoiseAndReportsItsStages) {
  const Record rec = MakeRecord(1 << 15, 0.1, 1);
  const auto r = RunWflp(rec.x, {});
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->denoised.size(), rec.x.size());
  EXPECT_EQ(r->summary.level, 4);
  EXPECT_EQ(r->summary.flp.num_samples, r->summary.approximation_length);
  EXPECT_EQ(r->summary.thresholds.threshold.size(), 4u);
  // Noise SD 0.1 on a signal slow compared with fs/32: removing the details above fs/32 and
  // smoothing the approximation leaves much less than the raw error (measured ~4x); factor 2.
  EXPECT_LT(Rms(r->denoised, rec.truth, 256), Rms(rec.x, rec.truth, 256) / 2.0);
  EXPECT_FALSE(r->summary.BriefReport().empty());
}

TEST(Wflp, DetailHandlingDoesWhatItSays) {
  const Record rec = MakeRecord(4096, 0.1, 2);
  WflpOptions keep, zero, thr;
  keep.details = DetailHandling::kKeep;
  zero.details = DetailHandling::kZero;
  const auto k = RunWflp(rec.x, keep);
  const auto z = RunWflp(rec.x, zero);
  const auto t = RunWflp(rec.x, thr);
  ASSERT_TRUE(k.ok() && z.ok() && t.ok());
  // keep - zero = the reconstruction of the details alone (the transform is linear), which is
  // the input minus the reconstruction of its approximation: check against an explicit DWT.
  const auto w = MakeWavelet("db4");
  auto d = WaveDec(rec.x, *w, ExtensionMode::kSymmetric, 4);
  ASSERT_TRUE(d.ok());
  std::fill(d->approximation.begin(), d->approximation.end(), 0.0);
  const auto details_only = WaveRec(*d, *w);
  ASSERT_TRUE(details_only.ok());
  double worst = 0.0;
  for (std::size_t i = 0; i < rec.x.size(); ++i) {
    worst = std::max(worst, std::abs(((*k).denoised[i] - (*z).denoised[i]) - (*details_only)[i]));
  }
  EXPECT_LT(worst, 1e-12);
  // Universal soft thresholding zeroes almost all white-noise details.
  for (double f : t->summary.thresholds.fraction_zeroed) EXPECT_GT(f, 0.9);
}

TEST(Wflp, OutputScalesWithInput) {
  const Record rec = MakeRecord(8192, 0.1, 3);
  std::vector<double> big(rec.x.size());
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = 1e6 * rec.x[i];
  const auto a = WflpDenoise(rec.x, {});
  const auto b = WflpDenoise(big, {});
  ASSERT_TRUE(a.ok() && b.ok());
  double worst = 0.0;
  for (std::size_t i = 0; i < big.size(); ++i) worst = std::max(worst, std::abs((*b)[i] - 1e6 * (*a)[i]));
  // DWT, MAD threshold and FLP are all homogeneous of degree 1: rounding only (1e-9 relative to
  // the 1e6 x O(1) signal).
  EXPECT_LT(worst, 1e-3);
}

TEST(Wflp, StableOverFiveMillionSamples) {
  // 5e6 samples (14 h at 100 Hz): no divergence, output finite and tracking the truth.
  const Record rec = MakeRecord(5000000, 0.1, 4);
  const auto r = RunWflp(rec.x, {});
  ASSERT_TRUE(r.ok()) << r.error().message;
  for (std::size_t i = 0; i < r->denoised.size(); ++i) ASSERT_TRUE(std::isfinite(r->denoised[i])) << i;
  const double raw = Rms(rec.x, rec.truth, 1000);
  EXPECT_LT(Rms(r->denoised, rec.truth, 1000), raw / 2.0);
  // The last 10% is as good as the whole: no slow drift of the adaptive weights.
  const std::size_t tail = rec.x.size() - rec.x.size() / 10;
  EXPECT_LT(Rms(r->denoised, rec.truth, tail), raw / 2.0);
}

TEST(Wflp, InvalidOptions) {
  WflpOptions o;
  o.flp.beta = 3.0;
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_EQ(why, "WflpOptions::flp.beta = 3: must be in (0, 2) (NLMS stability)");
  o = {};
  o.wavelet = "morlet";
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_EQ(why.rfind("WflpOptions::wavelet", 0), 0u) << why;
  EXPECT_EQ(RunWflp(std::vector<double>(10, 1.0), {}).error().kind, ErrorKind::kInvalidArgument);  // too short for level 4
  EXPECT_EQ(*ParseDetailHandling("keep"), DetailHandling::kKeep);
  EXPECT_FALSE(ParseDetailHandling("drop").has_value());
}

// Near the ends of the double range (fuzz_numeric_stages): see denoise_numeric_edges.h.
TEST(NumericEdges, WflpDenoiseNearTheEndsOfTheDoubleRange) {
  testing::ExpectDenoiseScaleFreeNearTheEndsOfTheDoubleRange(
      [](const std::vector<double>& x) { return WflpDenoise(x, WflpOptions{}); });
}

// The input checks the three denoisers share (normalising_scale.h SignalError): an empty or a
// non-finite signal is bad input, named by the denoiser and the sample.
TEST(Denoisers, EmptyOrNonFiniteSignalIsRefusedNamingTheDenoiserAndTheSample) {
  const std::vector<double> empty;
  std::vector<double> nan(200, 1.0);
  nan[7] = std::numeric_limits<double>::quiet_NaN();
  const auto expect = [](const Error& e, const std::string& message) {
    EXPECT_EQ(e.kind, ErrorKind::kInvalidInput) << e.message;
    EXPECT_EQ(e.message, message);
  };
  expect(RunFlp(empty, {}).error(), "FLP: empty signal");
  expect(RunFlp(nan, {}).error(), "FLP: sample 7 is not finite");
  expect(RunWflp(empty, {}).error(), "WFLP: empty signal");
  expect(RunWflp(nan, {}).error(), "WFLP: sample 7 is not finite");
  expect(RunWaveletDenoise(empty, {}).error(), "wavelet denoising: empty signal");
  expect(RunWaveletDenoise(nan, {}).error(), "wavelet denoising: sample 7 is not finite");
}

}  // namespace
}  // namespace gyrocomp
