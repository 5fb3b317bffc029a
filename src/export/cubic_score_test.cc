// Scores of an exported cubic (docs/explanation/accuracy-calibration.md): the firmware formulas
// against the cubic they carry, the residual block RMS against a hand computation, and the expected
// next-run error against its definition and the truth of held-out simulated runs.
#include "gyrocomp/export/cubic_score.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "export_test_models.h"
#include "gyrocomp/export/param_export.h"

namespace gyrocomp {
namespace {

TemperatureCubic SomeCubic() {
  TemperatureCubic c;
  c.ref_temp_c = 37.5;
  c.temp_min_c = 12.0;
  c.temp_max_c = 63.0;
  c.coeff = {2.0e-3, 3.0e-5, -2.0e-7, 4.0e-9};  // rad/s per C^k
  return c;
}

TEST(FirmwareCorrection, Px4IsTheCubicClampedInFloat) {
  const TemperatureCubic c = SomeCubic();
  std::vector<double> t;
  for (double x = 0.0; x <= 80.0; x += 0.37) t.push_back(x);
  const auto fw = FirmwareCorrection(FirmwareFormula::kPx4, c, t, 0.0);
  ASSERT_EQ(fw.size(), t.size());
  for (std::size_t i = 0; i < t.size(); ++i)
    EXPECT_NEAR(fw[i], c.Evaluate(std::clamp(t[i], 12.0, 63.0)), 2e-9) << t[i];
  // Clamped: flat outside [TMIN, TMAX].
  EXPECT_EQ(fw.front(), FirmwareCorrection(FirmwareFormula::kPx4, c, std::vector<double>{12.0}, 0.0)[0]);
}

TEST(FirmwareCorrection, ArduPilotIsRelativeToTheCalibrationTemperature) {
  const TemperatureCubic c = SomeCubic();
  std::vector<double> t;
  for (double x = 5.0; x <= 75.0; x += 0.53) t.push_back(x);
  for (double tcal : {20.0, 35.0, 70.0}) {
    const auto fw = FirmwareCorrection(FirmwareFormula::kArduPilot, c, t, tcal);
    const double at_cal = c.Evaluate(std::clamp(tcal, 12.0, 63.0));
    for (std::size_t i = 0; i < t.size(); ++i)
      EXPECT_NEAR(fw[i], c.Evaluate(std::clamp(t[i], 12.0, 63.0)) - at_cal, 2e-9) << t[i] << " Tcal " << tcal;
  }
}

TEST(ResidualBlockRms, MeansOfBlocksAboutTheirMean) {
  // Blocks of 2: means 1, 3, 5 (the partial last row dropped) -> about 3: RMS sqrt(8/3).
  const std::vector<double> v = {1.5, 0.5, 3.0, 3.0, 4.0, 6.0, 100.0};
  const std::vector<double> zero(v.size(), 0.0);
  auto r = ResidualBlockRms(v, zero, 2);
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(*r, std::sqrt(8.0 / 3.0), 1e-15);
  // The correction is subtracted before the means; a constant one changes nothing.
  std::vector<double> k(v.size(), 7.0);
  EXPECT_NEAR(*ResidualBlockRms(v, k, 2), *r, 1e-14);
  EXPECT_FALSE(ResidualBlockRms(v, zero, 0).ok());
  EXPECT_FALSE(ResidualBlockRms(v, zero, 4).ok());  // one block
  EXPECT_FALSE(ResidualBlockRms(v, std::vector<double>(3, 0.0), 2).ok());
}

class ExpectedError : public ::testing::Test {
 protected:
  void SetUp() override {
    run_ = export_test::ChamberRun(61);
    model_ = export_test::Fit(run_, DriftModelKind::kPolynomial, DriftInputSet::kTempAndRate);
    CubicProjectionOptions po;
    auto c = ProjectOntoCubic(model_, po);
    ASSERT_TRUE(c.ok());
    cubic_ = *c;
  }
  SimulatedRun run_;
  DriftModel model_;
  TemperatureCubic cubic_;
};

TEST_F(ExpectedError, IsTheProjectionAndTheBandInQuadrature) {
  ASSERT_TRUE(model_.band.has_value());
  auto e = ExpectedCubicError(model_, cubic_, DriftInputs{run_.temp_c, run_.fs_hz});
  ASSERT_TRUE(e.ok()) << e.error().message;
  EXPECT_EQ(e->level, model_.band->level);
  EXPECT_EQ(e->steady.num_samples, 401u);
  for (const CubicConditionError* c : {&e->steady, &*e->warm_up}) {
    EXPECT_GT(c->band_sd_rms, 0.0);
    EXPECT_NEAR(c->total_rms, std::hypot(c->projection_rms, c->band_sd_rms), 1e-15);
  }
  // Steady: the cubic is the least-squares projection of the state-0 curve, so its part is the
  // projection residual alone, far below the drift's span.
  EXPECT_LT(e->steady.projection_rms, 0.05 * export_test::Span(run_.true_drift_dps));
  // The paper's run holds cooling and heating: a warm-up condition exists.
  ASSERT_TRUE(e->warm_up.has_value());
  EXPECT_GT(e->warm_up->num_samples, 100u);
  // Without the calibration run only steady is known.
  auto s = ExpectedCubicError(model_, cubic_, std::nullopt);
  ASSERT_TRUE(s.ok());
  EXPECT_FALSE(s->warm_up.has_value());
  EXPECT_EQ(s->steady.total_rms, e->steady.total_rms);
}

TEST_F(ExpectedError, AModelWithoutABandSaysSo) {
  DriftModel old = model_;
  old.band.reset();
  auto e = ExpectedCubicError(old, cubic_, std::nullopt);
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().message.find("no prediction band"), std::string::npos);
  CubicExpectedErrorOptions bad;
  bad.grid_points = 3;
  EXPECT_FALSE(ExpectedCubicError(model_, cubic_, std::nullopt, bad).ok());
}

// The expected steady error is an error bound in the right units: on held-out runs of the same
// unit, the cubic's RMS error against the true static curve (state 0) is of its order (within a
// factor 4 either way over 4 seeds: the band is calibrated by bench/drift_band_coverage.py, this
// only catches a unit or scale slip).
TEST_F(ExpectedError, IsOfTheOrderOfTheHeldOutErrorAgainstTheTrueCurve) {
  auto e = ExpectedCubicError(model_, cubic_, std::nullopt);
  ASSERT_TRUE(e.ok());
  double ss = 0.0;
  int n = 0;
  for (std::uint64_t seed : {71, 72, 73, 74}) {
    const SimulatedRun held = export_test::ChamberRun(seed);
    // Held-out error of the cubic against the run's true drift, constant removed.
    double mean = 0.0;
    std::vector<double> d(held.temp_c.size());
    for (std::size_t i = 0; i < d.size(); ++i) mean += (d[i] = cubic_.Evaluate(held.temp_c[i]) - held.true_drift_dps[i]);
    mean /= static_cast<double>(d.size());
    for (double x : d) ss += (x - mean) * (x - mean), ++n;
  }
  const double held_rms = std::sqrt(ss / n);
  EXPECT_GT(e->steady.total_rms, held_rms / 4.0) << held_rms;
  EXPECT_LT(e->steady.total_rms, held_rms * 4.0) << held_rms;
}

}  // namespace
}  // namespace gyrocomp
