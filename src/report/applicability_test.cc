// The not-applicable rule (applicability.h) on closed-form ADEV curves, both sides of each clause.
#include "gyrocomp/report/applicability.h"

#include <cmath>
#include <functional>

#include <gtest/gtest.h>

namespace gyrocomp {
namespace {

// An octave curve tau = 0.2 s * 2^k, k = 0..15, with adev = f(tau); terms as a caller sets them.
AllanResult Curve(const std::function<double(double)>& f) {
  AllanResult a;
  a.fs_hz = 5.0;
  for (int k = 0; k < 16; ++k) {
    const double tau = 0.2 * std::pow(2.0, k);
    a.curve.tau_s.push_back(tau);
    a.curve.adev_dps.push_back(f(tau));
  }
  a.terms.arw_deg_per_sqrt_h = 60.0 * f(1.0);
  return a;
}

AllanResult PowerLaw(double slope) {
  return Curve([slope](double tau) { return 0.01 * std::pow(tau, slope); });
}

TEST(FittedLogLogSlope, ExactOnPowerLawsAndNeedsTwoTaus) {
  for (double s : {-1.0, -0.5, 0.0, 0.5, 0.85}) {
    auto slope = FittedLogLogSlope(PowerLaw(s).curve, 0.5, 2.0);
    ASSERT_TRUE(slope.has_value());
    EXPECT_NEAR(*slope, s, 1e-12);
  }
  EXPECT_FALSE(FittedLogLogSlope(PowerLaw(-0.5).curve, 0.7, 1.0).has_value());  // one tau (0.8 s)
}

TEST(ArwApplicability, WhiteNoiseWithItsBandwidthIsApplicable) {
  const TermApplicability t = ArwApplicability(PowerLaw(-0.5), 2.5);
  EXPECT_TRUE(t.applicable) << t.reason;
  EXPECT_TRUE(t.reason.empty());
  EXPECT_NEAR(*t.fitted_slope, -0.5, 1e-12);
}

TEST(ArwApplicability, SlopeToleranceBothSides) {
  // Tolerance 0.2: -0.5 + 0.19 is white enough, -0.5 + 0.21 is not (and symmetrically).
  EXPECT_TRUE(ArwApplicability(PowerLaw(-0.31), 2.5).applicable);
  EXPECT_TRUE(ArwApplicability(PowerLaw(-0.69), 2.5).applicable);
  const TermApplicability up = ArwApplicability(PowerLaw(-0.29), 2.5);
  EXPECT_FALSE(up.applicable);
  EXPECT_NE(up.reason.find("slope there is -0.29"), std::string::npos) << up.reason;
  EXPECT_FALSE(ArwApplicability(PowerLaw(-0.71), 2.5).applicable);
  // The demo's processed output: +0.85 at 1 s.
  EXPECT_FALSE(ArwApplicability(PowerLaw(0.85), 2.5).applicable);
}

TEST(ArwApplicability, NeedsTheBandwidthAndTausAboveItsInverse) {
  const TermApplicability none = ArwApplicability(PowerLaw(-0.5), std::nullopt);
  EXPECT_FALSE(none.applicable);
  EXPECT_NE(none.reason.find("bandwidth not measured"), std::string::npos);
  // Read over [0.5, 2] s: 1/(2B) = 0.5 s at B = 1 Hz is the boundary.
  EXPECT_TRUE(ArwApplicability(PowerLaw(-0.5), 1.0).applicable);
  EXPECT_FALSE(ArwApplicability(PowerLaw(-0.5), 0.99).applicable);
  // A raw record at any rate: 1/(2 x Nyquist) = its sample period, the shortest tau (2 Hz: 0.5 s).
  EXPECT_TRUE(ArwApplicability(PowerLaw(-0.5), 2.0 / 2.0).applicable);
  // A white curve low-passed to 0.175 Hz: read from 0.5 s < 1/(2B) = 2.86 s.
  const TermApplicability lp = ArwApplicability(PowerLaw(-0.5), 0.175);
  EXPECT_FALSE(lp.applicable);
  EXPECT_NE(lp.reason.find("1/(2 bandwidth) = 2.86 s"), std::string::npos) << lp.reason;
}

AllanResult WithRrwRegion(double slope, double lo, double hi) {
  AllanResult a = Curve([slope](double tau) { return 0.001 * std::pow(tau, slope); });
  a.terms.rrw_deg_per_h_per_sqrt_h = 1.0;
  a.terms.rrw_fit_tau_min_s = lo;
  a.terms.rrw_fit_tau_max_s = hi;
  return a;
}

TEST(RrwApplicability, SlopeToleranceBothSides) {
  EXPECT_TRUE(RrwApplicability(WithRrwRegion(0.5, 819.2, 3276.8), 2.5).applicable);
  EXPECT_TRUE(RrwApplicability(WithRrwRegion(0.69, 819.2, 3276.8), 2.5).applicable);
  EXPECT_TRUE(RrwApplicability(WithRrwRegion(0.31, 819.2, 3276.8), 2.5).applicable);
  EXPECT_FALSE(RrwApplicability(WithRrwRegion(0.71, 819.2, 3276.8), 2.5).applicable);
  EXPECT_FALSE(RrwApplicability(WithRrwRegion(0.29, 819.2, 3276.8), 2.5).applicable);
}

TEST(RrwApplicability, RegionMadeByTheLowPassIsNotApplicable) {
  // The demo's "RRW after": a +1/2 secant over [1.6, 3.2] s of a 0.175 Hz output.
  const TermApplicability t = RrwApplicability(WithRrwRegion(0.52, 1.6, 3.2), 0.175);
  EXPECT_FALSE(t.applicable);
  EXPECT_NEAR(*t.fitted_slope, 0.52, 1e-12);
  EXPECT_NE(t.reason.find("1/(2 bandwidth)"), std::string::npos) << t.reason;
  // The same region at the raw Nyquist bandwidth is fine, and 1/(2B) equal to its start too.
  EXPECT_TRUE(RrwApplicability(WithRrwRegion(0.52, 1.6, 3.2), 2.5).applicable);
  EXPECT_TRUE(RrwApplicability(WithRrwRegion(0.52, 1.6, 3.2), 1.0 / 3.2).applicable);
  EXPECT_FALSE(RrwApplicability(WithRrwRegion(0.52, 1.6, 3.2), 0.99 / 3.2).applicable);
}

TEST(RrwApplicability, NoRegionIsNotApplicable) {
  AllanResult a = PowerLaw(-0.5);
  const TermApplicability t = RrwApplicability(a, 2.5);
  EXPECT_FALSE(t.applicable);
  EXPECT_NE(t.reason.find("no +1/2 region"), std::string::npos);
}

TEST(TermApplicabilityOptions, IsValid) {
  std::string why;
  EXPECT_TRUE(TermApplicabilityOptions{}.IsValid(&why));
  TermApplicabilityOptions o;
  o.slope_tolerance = 0.0;
  EXPECT_FALSE(o.IsValid(&why));
  o = {};
  o.arw_tau_span = 0.5;
  EXPECT_FALSE(o.IsValid(&why));
}

}  // namespace
}  // namespace gyrocomp
