// Tests of MDEV, HDEV, OHDEV and TOTDEV: golden vectors (allantools on a record with linear drift),
// closed forms (white rate noise: MDEV slope -1; Hadamard blind to a ramp), errors.
#include "gyrocomp/allan/deviations.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/sim/simulator.h"  // NormalGenerator
#include "test_support.h"

namespace gyrocomp {
namespace {

using testing::WhiteNoise;

void ExpectMatchesGolden(DeviationKind kind) {
  const auto csv = testing::ReadGoldenCsv(testing::GoldenPath("allan_kinds/rate.csv"));
  const auto golden = testing::ReadJsonFile(testing::GoldenPath("allan_kinds/deviations.json"));
  const std::string name = kind == DeviationKind::kAdev ? "oadev" : DeviationKindName(kind);
  ASSERT_TRUE(golden.contains(name)) << name;
  const auto& g = golden[name];
  Result<DeviationCurve> r = ComputeDeviation(csv.at("rate_dps"), golden["fs_hz"].get<double>(), kind);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto tau = g["tau_s"].get<std::vector<double>>();
  const auto dev = g["dev_dps"].get<std::vector<double>>();
  const auto err = g["error_dps"].get<std::vector<double>>();
  const auto n = g["n"].get<std::vector<double>>();
  ASSERT_EQ(r->size(), tau.size()) << name;
  for (std::size_t j = 0; j < tau.size(); ++j) {
    // 1e-9 relative (the bar): the same double-precision formulas on the same phase
    // record; only the summation order differs (numpy pairwise or cumsum vs our blocked and
    // running sums), ~1e-12 relative for 2e4 terms. A wrong count n, normalisation, stride or
    // reflection is off by far more.
    EXPECT_NEAR(r->tau_s[j], tau[j], 1e-12 * tau[j]) << name << " j=" << j;
    EXPECT_NEAR(r->dev_dps[j], dev[j], 1e-9 * dev[j]) << name << " tau=" << tau[j];
    EXPECT_NEAR(r->error_dps[j], err[j], 1e-9 * err[j]) << name << " tau=" << tau[j];
    EXPECT_EQ(r->n[j], static_cast<std::int64_t>(n[j])) << name << " tau=" << tau[j];
    EXPECT_LT(r->lo_dps[j], r->dev_dps[j]);
    EXPECT_GT(r->hi_dps[j], r->dev_dps[j]);
    EXPECT_GE(r->edf[j], 1.0);
  }
}

TEST(DeviationGolden, AdevMatchesAllantoolsOadev) { ExpectMatchesGolden(DeviationKind::kAdev); }
TEST(DeviationGolden, MdevMatchesAllantools) { ExpectMatchesGolden(DeviationKind::kMdev); }
TEST(DeviationGolden, HdevMatchesAllantools) { ExpectMatchesGolden(DeviationKind::kHdev); }
TEST(DeviationGolden, OhdevMatchesAllantools) { ExpectMatchesGolden(DeviationKind::kOhdev); }
TEST(DeviationGolden, TotdevMatchesAllantools) { ExpectMatchesGolden(DeviationKind::kTotdev); }

// White rate noise sigma at fs: AVAR(tau) = sigma^2 / (fs tau) exactly in expectation; MVAR is
// half of it at large m (SP 1065: Mod sigma^2 / sigma^2 -> 0.5 for white FM), HVAR equals AVAR
// for white FM, TOTVAR equals AVAR. 2e5 samples: at tau = 16/fs the overlapping estimators
// have thousands of degrees of freedom, so 5% is several standard errors.
TEST(DeviationClosedForm, WhiteRateNoiseRatios) {
  const double fs = 100.0, sigma = 0.1;
  const auto y = WhiteNoise(200000, sigma, 7);
  const double tau = 16.0 / fs;
  const double adev_theory = sigma / std::sqrt(fs * tau);
  struct Case {
    DeviationKind kind;
    double ratio;  // dev / adev_theory
  };
  for (const Case& c : {Case{DeviationKind::kAdev, 1.0}, Case{DeviationKind::kMdev, std::sqrt(0.5)},
                        Case{DeviationKind::kOhdev, 1.0}, Case{DeviationKind::kTotdev, 1.0}}) {
    Result<DeviationCurve> r = ComputeDeviation(y, fs, c.kind);
    ASSERT_TRUE(r.ok()) << r.error().message;
    bool found = false;
    for (std::size_t j = 0; j < r->size(); ++j) {
      if (r->m[j] != 16) continue;
      found = true;
      // MVAR/AVAR for white FM at m = 16 is 0.5 within ~0.3% (SP 1065 Fig. 10): inside 5%.
      EXPECT_NEAR(r->dev_dps[j] / adev_theory, c.ratio, 0.05 * c.ratio) << DeviationKindName(c.kind);
    }
    EXPECT_TRUE(found) << DeviationKindName(c.kind);
  }
}

TEST(DeviationClosedForm, RampRaisesAdevAndHadamardIsBlindToIt) {
  // Rate y_i = a * t_i (deg/s), t_i = i / fs. ADEV of a ramp: a tau / sqrt(2) (IEEE 952 Table).
  // Hadamard of a ramp: the third difference of the phase of a linear rate is zero, so HDEV and
  // OHDEV are 0 up to rounding, while ADEV = a tau / sqrt(2).
  const double fs = 10.0, a = 1e-3;
  std::vector<double> y(20000);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = a * static_cast<double>(i) / fs;
  Result<DeviationCurve> adev = ComputeDeviation(y, fs, DeviationKind::kAdev);
  Result<DeviationCurve> ohdev = ComputeDeviation(y, fs, DeviationKind::kOhdev);
  Result<DeviationCurve> hdev = ComputeDeviation(y, fs, DeviationKind::kHdev);
  ASSERT_TRUE(adev.ok() && ohdev.ok() && hdev.ok());
  for (std::size_t j = 0; j < adev->size(); ++j) {
    // Exact for a discrete ramp too: the second difference of the averages is a tau. 1e-6: the
    // phase is a quadratic of size ~1e3 deg, summed and differenced in double.
    EXPECT_NEAR(adev->dev_dps[j], a * adev->tau_s[j] / std::sqrt(2.0), 1e-6 * a * adev->tau_s[j]);
  }
  for (const DeviationCurve* h : {&*ohdev, &*hdev}) {
    for (std::size_t j = 0; j < h->size(); ++j) {
      // Rounding only: phase values up to ~2e4 * 2e3 * 1e-3 / 10 = 4e3 deg, eps ~ 1e-12 deg per
      // term, divided by tau >= 0.1 s: < 1e-9 deg/s, vs ADEV's 7e-5 deg/s at the shortest tau.
      EXPECT_LT(h->dev_dps[j], 1e-8) << "tau=" << h->tau_s[j];
    }
  }
}

TEST(DeviationKinds, NamesRoundTripAndErrors) {
  for (const char* s : {"adev", "mdev", "hdev", "ohdev", "totdev"}) {
    const auto k = ParseDeviationKind(s);
    ASSERT_TRUE(k.has_value()) << s;
    EXPECT_STREQ(DeviationKindName(*k), s);
  }
  EXPECT_FALSE(ParseDeviationKind("oadev").has_value());
  EXPECT_FALSE(ParseDeviationKind("").has_value());
  const std::vector<double> three = {1, 2, 3};
  Result<DeviationCurve> r = ComputeDeviation(three, 1.0, DeviationKind::kMdev);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().kind, ErrorKind::kInvalidInput);
  std::vector<double> bad = {1, 2, NAN, 4, 5};
  r = ComputeDeviation(bad, 1.0, DeviationKind::kTotdev);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("sample 2"), std::string::npos) << r.error().message;
  r = ComputeDeviation(WhiteNoise(100, 1.0, 1), 0.0, DeviationKind::kOhdev);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().kind, ErrorKind::kInvalidInput);
}

// Found by fuzz_numeric_stages: a record alternating near the largest double gave a finite
// Hadamard deviation but an infinite upper confidence bound with a success status. Every kind:
// refused with a message, or every value finite.
TEST(Deviations, NearTheLargestDoubleIsRefusedOrFinite) {
  std::vector<double> y = {-1.37153e303, 1.37153e303, -1.37153e303, 1.37153e303, -1.37153e303,
                           1.37153e303, -1.37153e303, 1.79769e308, -1.79769e308, 1.79769e308};
  for (DeviationKind k : {DeviationKind::kAdev, DeviationKind::kMdev, DeviationKind::kHdev, DeviationKind::kOhdev,
                          DeviationKind::kTotdev}) {
    SCOPED_TRACE(DeviationKindName(k));
    const Result<DeviationCurve> d = ComputeDeviation(y, 1.0, k);
    if (!d.ok()) {
      EXPECT_FALSE(d.error().message.empty());
      continue;
    }
    for (std::size_t j = 0; j < d->size(); ++j) {
      EXPECT_TRUE(std::isfinite(d->dev_dps[j]) && std::isfinite(d->lo_dps[j]) && std::isfinite(d->hi_dps[j])) << j;
    }
  }
}

}  // namespace
}  // namespace gyrocomp
