// Every noise figure states its support (AllanNoiseTerms::unsupported): on logs of 1-10 samples
// and on sub-second logs each figure is either carried by the curve or marked unsupported with
// its reason, never a number without support; nothing is projected past the record.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/allan/allan.h"

namespace gyrocomp {
namespace {

std::vector<double> WhiteNoise(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 0.05);
  std::vector<double> v(n);
  for (double& x : v) x = g(rng);
  return v;
}

// 1-2 samples carry no curve at all: refused (a returned error naming what is missing).
TEST(AllanSupportTest, OneAndTwoSamplesHaveNoCurve) {
  for (std::size_t n : {1u, 2u}) {
    const std::vector<double> v = WhiteNoise(n, 1);
    Result<AllanResult> r = ComputeAllan(v, 100.0);
    EXPECT_FALSE(r.ok()) << n;
  }
}

// The curve's minimum and B need 3 taus: 3-8 samples (1-2 octave taus) have none.
TEST(AllanSupportTest, MinimumAndBiasInstabilityNeedThreeTaus) {
  for (std::size_t n = 3; n <= 10; ++n) {
    Result<AllanResult> r = ComputeAllan(WhiteNoise(n, 2), 100.0);
    ASSERT_TRUE(r.ok()) << n << ": " << r.error().message;
    const bool enough = r->curve.size() >= kMinTausForMinimum;
    EXPECT_EQ(r->terms.Supported("adev_min_deg_per_h"), enough) << n;
    EXPECT_EQ(r->terms.Supported("bias_instability_deg_per_h"), enough) << n;
    if (!enough) {
      const auto& u = r->terms.unsupported.at("adev_min_deg_per_h");
      EXPECT_EQ(u.reason, "fewer_than_3_taus");
      ASSERT_TRUE(u.needs_record_s.has_value());
      EXPECT_DOUBLE_EQ(*u.needs_record_s, 0.08);  // 9 samples at 100 Hz
      EXPECT_NE(r->BriefReport().find("ADEV min n/a (" + u.text), std::string::npos) << r->BriefReport();
    }
  }
  // 9 samples: taus of 1, 2 and 4 samples.
  Result<AllanResult> r = ComputeAllan(WhiteNoise(9, 2), 100.0);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->curve.size(), 3u);
  EXPECT_TRUE(r->terms.Supported("adev_min_deg_per_h"));
}

// The EDF-qualified minimum: no tau of a 1-10 sample log reaches EDF 10 (a 6-sample
// log printed "EDF >= 10: 596.1 deg/h"); it is n/a with its reason, and so are the figures
// anchored on it.
TEST(AllanSupportTest, UsableMinimumNeedsATauWithTheStatedEdf) {
  for (std::size_t n = 3; n <= 10; ++n) {
    Result<AllanResult> r = ComputeAllan(WhiteNoise(n, 3), 100.0);
    ASSERT_TRUE(r.ok());
    bool any = false;
    for (double e : r->curve.edf) any = any || e >= r->terms.min_edf;
    EXPECT_EQ(r->terms.Supported("adev_min_usable_deg_per_h"), any) << n;
    if (!any) {
      EXPECT_EQ(r->terms.unsupported.at("adev_min_usable_deg_per_h").reason, "no_tau_with_edf_ge_min_edf");
      EXPECT_FALSE(r->terms.Supported("arw_fit_deg_per_sqrt_h"));
      EXPECT_FALSE(r->terms.Supported("rrw_deg_per_h_per_sqrt_h"));
      EXPECT_NE(r->BriefReport().find("EDF >= 10: n/a (no tau has EDF >= 10"), std::string::npos) << r->BriefReport();
    }
  }
  // A long white-noise record: supported.
  Result<AllanResult> r = ComputeAllan(WhiteNoise(20000, 3), 100.0);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->terms.Supported("adev_min_usable_deg_per_h"));
  EXPECT_TRUE(r->terms.Supported("adev_min_deg_per_h"));
}

// ARW sigma(1 s): a sub-second record does not reach 1 s ... unless 1 s is below the first tau;
// here 0.5 s of 100 Hz data: n/a with the record it needs (2 s).
TEST(AllanSupportTest, ArwNeedsOneSecondInTheRecord) {
  Result<AllanResult> r = ComputeAllan(WhiteNoise(50, 4), 100.0);
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(r->terms.Supported("arw_deg_per_sqrt_h"));
  const auto& u = r->terms.unsupported.at("arw_deg_per_sqrt_h");
  if (u.reason == "record_too_short_for_tau") {
    ASSERT_TRUE(u.needs_record_s.has_value());
    EXPECT_DOUBLE_EQ(*u.needs_record_s, 2.0);
  }
  EXPECT_NE(r->BriefReport().find("ARW n/a ("), std::string::npos) << r->BriefReport();
  // 30 s of 100 Hz white noise: carried.
  Result<AllanResult> ok = ComputeAllan(WhiteNoise(3000, 4), 100.0);
  ASSERT_TRUE(ok.ok());
  EXPECT_TRUE(ok->terms.Supported("arw_deg_per_sqrt_h"));
  EXPECT_TRUE(ok->terms.arw_deg_per_sqrt_h.has_value());
}

// The -1/2 fit over fewer than 2 taus is no fit.
TEST(AllanSupportTest, ArwFitNeedsTwoTaus) {
  for (std::size_t n = 3; n <= 10; ++n) {
    Result<AllanResult> r = ComputeAllan(WhiteNoise(n, 5), 100.0);
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(r->terms.Supported("arw_fit_deg_per_sqrt_h")) << n;
  }
}

// RRW = sigma(3 s) on the +1/2 line: never from a one-tau fit, never past the record. A random
// walk of 0.97 s at 50 Hz (a fit over [0.04, 0.04] s was once projected to 3 s) is n/a.
TEST(AllanSupportTest, RrwIsNeverProjectedPastTheRecord) {
  std::mt19937 rng(6);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> walk(49);
  double acc = 0.0;
  for (double& x : walk) x = (acc += g(rng));
  Result<AllanResult> r = ComputeAllan(walk, 50.0);
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(r->terms.Supported("rrw_deg_per_h_per_sqrt_h")) << r->BriefReport();
  EXPECT_NE(r->BriefReport().find("RRW n/a ("), std::string::npos) << r->BriefReport();
  // 200 s of a random walk at 50 Hz: sigma(3 s) is inside the record and the +1/2 region is long.
  std::vector<double> longer(10000);
  acc = 0.0;
  for (double& x : longer) x = (acc += 0.01 * g(rng));
  Result<AllanResult> ok = ComputeAllan(longer, 50.0);
  ASSERT_TRUE(ok.ok());
  if (ok->terms.rrw_deg_per_h_per_sqrt_h) {
    EXPECT_TRUE(ok->terms.Supported("rrw_deg_per_h_per_sqrt_h")) << ok->terms.unsupported.begin()->second.text;
  }
}

// Every figure of every short log: supported, or unsupported with a reason key and a text.
TEST(AllanSupportTest, EveryFigureOfShortLogsHasSupportOrAReason) {
  for (double fs : {1.0, 10.0, 100.0}) {
    for (std::size_t n = 3; n <= 10; ++n) {
      Result<AllanResult> r = ComputeAllan(WhiteNoise(n, 7), fs);
      ASSERT_TRUE(r.ok());
      for (const auto& [key, u] : r->terms.unsupported) {
        EXPECT_FALSE(u.reason.empty()) << key;
        EXPECT_FALSE(u.text.empty()) << key;
        EXPECT_EQ(r->BriefReport().find("nan"), std::string::npos);
      }
      // No tau reaches EDF 10 with 10 samples, so none of the EDF-anchored figures is given.
      for (const char* key : {"adev_min_usable_deg_per_h", "arw_fit_deg_per_sqrt_h", "rrw_deg_per_h_per_sqrt_h"}) {
        EXPECT_FALSE(r->terms.Supported(key)) << key << " n=" << n;
      }
    }
  }
}

}  // namespace
}  // namespace gyrocomp
