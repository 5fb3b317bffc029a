// Wavelet-threshold denoising: PyWavelets golden signals, closed-form threshold cases, SURE.
#include "gyrocomp/denoise/wavelet_denoise.h"

#include <cmath>
#include <limits>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fixtures.h"
#include "test_support.h"
#include "denoise_numeric_edges.h"

namespace gyrocomp {
namespace {

using testing::GoldenPath;
using testing::ReadGoldenCsv;
using testing::ReadJsonFile;

double Rms(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s / static_cast<double>(a.size()));
}

TEST(WaveletDenoiseGolden, UniversalSoftMatchesPyWavelets) {
  const std::vector<double> x = ReadGoldenCsv(GoldenPath("wavelet/input.csv")).at("x");
  const nlohmann::json golden = ReadJsonFile(GoldenPath("wavelet/wavedec.json"));
  ASSERT_NE(std::string(golden["denoise_rule"]).find("median(|cD1|)/0.6745"), std::string::npos);
  for (const auto& c : golden["cases"]) {
    SCOPED_TRACE(std::string(c["wavelet"]) + " " + std::string(c["mode"]));
    WaveletDenoiseOptions o;
    o.wavelet = c["wavelet"];
    o.extension = *ParseExtensionMode(std::string(c["mode"]));
    o.level = c["level"].get<int>();
    o.threshold = ThresholdRule::kUniversal;
    o.threshold_mode = ThresholdMode::kSoft;
    const auto r = RunWaveletDenoise(x, o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const auto& u = c["universal_soft"];
    // sigma and threshold: a median and a product, exact up to rounding: 1e-14 relative.
    EXPECT_NEAR(r->summary.sigma[0], u["sigma"].get<double>(), 1e-14 * u["sigma"].get<double>());
    EXPECT_NEAR(r->summary.threshold[0], u["threshold"].get<double>(), 1e-14 * u["threshold"].get<double>());
    const std::vector<double> expected = u["denoised"];
    ASSERT_EQ(r->denoised.size(), expected.size());
    // 1e-10 (the bound). Measured ~1e-16: same coefficients (1e-17, wavelet_test), same
    // threshold formula; only a coefficient lying within rounding of the threshold could differ
    // more, and none does here.
    double worst = 0.0;
    for (std::size_t i = 0; i < expected.size(); ++i) worst = std::max(worst, std::abs(r->denoised[i] - expected[i]));
    EXPECT_LT(worst, 1e-10);
    // Every level used the same (finest-level) sigma and threshold.
    for (double t : r->summary.threshold) EXPECT_EQ(t, r->summary.threshold[0]);
  }
}

TEST(Threshold, SoftAndHardClosedForm) {
  std::vector<double> soft = {-3.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.5};
  std::vector<double> hard = soft;
  ApplyThreshold(soft, 1.0, ThresholdMode::kSoft);
  ApplyThreshold(hard, 1.0, ThresholdMode::kHard);
  const std::vector<double> soft_expected = {-2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.5};
  const std::vector<double> hard_expected = {-3.0, -1.0, 0.0, 0.0, 0.0, 1.0, 2.5};  // |x| >= thr kept (pywt)
  for (std::size_t i = 0; i < soft.size(); ++i) {
    EXPECT_DOUBLE_EQ(soft[i], soft_expected[i]) << i;
    EXPECT_DOUBLE_EQ(hard[i], hard_expected[i]) << i;
  }
  std::vector<double> zero_thr = {0.0, 1.0};
  ApplyThreshold(zero_thr, 0.0, ThresholdMode::kSoft);  // no 0/0
  EXPECT_EQ(zero_thr[0], 0.0);
  EXPECT_EQ(zero_thr[1], 1.0);
  // MAD of an even count: numpy's median averages the two middle values.
  const std::vector<double> d = {1.0, -4.0, 2.0, -3.0};
  EXPECT_DOUBLE_EQ(MadSigma(d), 2.5 / 0.6745);
}

TEST(WaveletDenoise, KnownSigmaGivesTheUniversalThreshold) {
  std::vector<double> x(4096);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0.0, 0.3);
  for (double& v : x) v = g(rng);
  WaveletDenoiseOptions o;
  o.noise_sigma = 0.3;
  const auto r = RunWaveletDenoise(x, o);
  ASSERT_TRUE(r.ok());
  EXPECT_DOUBLE_EQ(r->summary.threshold[0], 0.3 * std::sqrt(2.0 * std::log(4096.0)));
  // Pure white noise: the universal threshold exceeds the noise maximum with high probability,
  // so almost every detail coefficient is zeroed (VisuShrink's design).
  for (double z : r->summary.fraction_zeroed) EXPECT_GT(z, 0.99);
}

// A smooth signal in white noise: every rule reduces the error, soft and hard.
TEST(WaveletDenoise, EveryRuleReducesTheErrorOnASmoothSignal) {
  const std::size_t n = 8192;
  std::vector<double> truth(n), x(n);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0.0, 0.5);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / n;
    truth[i] = std::sin(2 * std::numbers::pi * 3 * t) + 0.5 * std::sin(2 * std::numbers::pi * 11 * t) + (t > 0.5 ? 1.0 : 0.0);
    x[i] = truth[i] + g(rng);
  }
  const double raw = Rms(x, truth);
  for (ThresholdRule rule : {ThresholdRule::kUniversal, ThresholdRule::kUniversalLevelDependent, ThresholdRule::kSure}) {
    for (ThresholdMode mode : {ThresholdMode::kSoft, ThresholdMode::kHard}) {
      WaveletDenoiseOptions o;
      o.wavelet = "sym8";
      o.level = 6;
      o.threshold = rule;
      o.threshold_mode = mode;
      const auto r = RunWaveletDenoise(x, o);
      ASSERT_TRUE(r.ok()) << r.error().message;
      // Noise SD 0.5 over 8192 samples; denoising at level 6 keeps the smooth part. A factor 2.5
      // is far below what each rule reaches (measured 3-6x) and far above chance.
      EXPECT_LT(Rms(r->denoised, truth), raw / 2.5) << ThresholdRuleName(rule) << " " << ThresholdModeName(mode);
      // SURE never exceeds the universal threshold; the MAD sigma is close to the true 0.5 at D1.
      EXPECT_NEAR(r->summary.sigma[0], 0.5, 0.05);
      if (rule == ThresholdRule::kSure) {
        for (std::size_t l = 0; l < r->summary.threshold.size(); ++l) {
          EXPECT_LE(r->summary.threshold[l], r->summary.sigma[l] * std::sqrt(2 * std::log(static_cast<double>(n))) + 1e-12);
        }
      }
    }
  }
}

TEST(WaveletDenoise, ErrorsAreReturned) {
  const std::vector<double> x(100, 1.0);
  WaveletDenoiseOptions bad;
  bad.wavelet = "db99";
  std::string why;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("WaveletDenoiseOptions::wavelet"), std::string::npos) << why;
  EXPECT_EQ(RunWaveletDenoise(x, bad).error().kind, ErrorKind::kInvalidArgument);
  WaveletDenoiseOptions deep;
  deep.level = 10;
  const auto r = RunWaveletDenoise(x, deep);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("deepest level"), std::string::npos) << r.error().message;
  std::vector<double> nan = x;
  nan[42] = std::nan("");
  const auto n = RunWaveletDenoise(nan, {});
  ASSERT_FALSE(n.ok());
  EXPECT_EQ(n.error().kind, ErrorKind::kInvalidInput);
  EXPECT_NE(n.error().message.find("sample 42"), std::string::npos);
  WaveletDenoiseOptions neg;
  neg.noise_sigma = -1.0;
  EXPECT_FALSE(neg.IsValid(&why));
  EXPECT_EQ(*ParseThresholdRule("sure"), ThresholdRule::kSure);
  EXPECT_FALSE(ParseThresholdMode("garrote").has_value());
}

// ---- gyrocomp denoise (end to end) ------------------------------------------------------------

class DenoiseCli : public testing::CliTest {
 protected:
  DenoiseCli() : CliTest("denoise_cli") {}
};

TEST_F(DenoiseCli, GoldenRuleThroughTheCommandLine) {
  std::string out;
  const int rc = Run("denoise -i " + GoldenPath("wavelet/input.csv") +
                         " --fs 1 --rate-col x --method wavelet --wavelet db4 --level 4"
                         " --threshold universal --threshold-mode soft -o " +
                         dir_ + "/out.csv --json " + dir_ + "/out.json",
                     &out);
  ASSERT_EQ(rc, 0) << out;
  const auto table = ReadGoldenCsv(dir_ + "/out.csv");
  ASSERT_TRUE(table.count("x") && table.count("denoised_dps")) << "columns: input plus denoised_dps";
  const nlohmann::json golden = ReadJsonFile(GoldenPath("wavelet/wavedec.json"));
  const std::vector<double> expected = golden["cases"][0]["universal_soft"]["denoised"];
  ASSERT_EQ(std::string(golden["cases"][0]["wavelet"]), "db4");
  ASSERT_EQ(table.at("denoised_dps").size(), expected.size());
  // The CSV holds shortest round-trip doubles, so the 1e-10 library bound applies unchanged.
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(table.at("denoised_dps")[i], expected[i], 1e-10);
  const nlohmann::json j = ReadJsonFile(dir_ + "/out.json");
  EXPECT_EQ(j["method"], "wavelet");
  EXPECT_TRUE(j.contains("arw_before_deg_per_sqrt_h") && j.contains("arw_after_deg_per_sqrt_h"));
}

TEST_F(DenoiseCli, BadInputExitsTwoWithoutOutput) {
  testing::WriteFile(dir_ + "/bad.csv", "time_s,rate_dps\n0,1\n0.01,abc\n0.02,3\n");
  std::string out;
  int rc = Run("denoise -i " + dir_ + "/bad.csv --method flp -o " + dir_ + "/o.csv", &out);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("bad.csv:3"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/o.csv"));
  rc = Run("denoise -i " + GoldenPath("wavelet/input.csv") + " --fs 1 --rate-col x --method wflp --level 12 -o " +
               dir_ + "/o.csv",
           &out);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("deepest level is 7"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/o.csv"));
  rc = Run("denoise -i " + GoldenPath("wavelet/input.csv") + " --fs 1 --rate-col x --method median", &out);
  EXPECT_EQ(rc, 2) << out;
}

// Near the ends of the double range (fuzz_numeric_stages): see denoise_numeric_edges.h.
TEST(NumericEdges, WaveletDenoiseNearTheEndsOfTheDoubleRange) {
  testing::ExpectDenoiseScaleFreeNearTheEndsOfTheDoubleRange(
      [](const std::vector<double>& x) { return WaveletDenoise(x, WaveletDenoiseOptions{}); });
}

}  // namespace
}  // namespace gyrocomp
