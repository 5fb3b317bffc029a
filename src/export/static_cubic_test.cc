// The static curve with every temperature weighted alike (static_cubic.h).
#include "gyrocomp/export/static_cubic.h"

#include <cmath>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "export_test_models.h"

namespace gyrocomp {
namespace {

double Cubic(double t) {
  const double d = t - 20.0;
  return 0.03 + 2.0e-3 * d - 1.5e-5 * d * d + 2.0e-7 * d * d * d;
}

// Data that are a cubic in T: the cubic comes back whatever the model and the dwell times.
TEST(StaticCubicByTemperature, RecoversACubicExactly) {
  const SimulatedRun run = export_test::ChamberRun(81);
  SimulatedRun exact = run;
  for (std::size_t i = 0; i < run.temp_c.size(); ++i) exact.rate_dps[i] = Cubic(run.temp_c[i]);
  for (DriftInputSet inputs : {DriftInputSet::kTemp, DriftInputSet::kTempAndRate}) {
    const DriftModel m = export_test::Fit(exact, DriftModelKind::kPolynomial, inputs);
    auto c = FitStaticCubicByTemperature(m, {run.temp_c, run.fs_hz}, exact.rate_dps);
    ASSERT_TRUE(c.ok()) << c.error().message;
    for (double t = c->temp_min_c; t <= c->temp_max_c; t += 0.5) EXPECT_NEAR(c->Evaluate(t), Cubic(t), 1e-7) << t;  // the fit's own rounding
  }
}

// The model's dynamic part is removed before binning: the model's own prediction as data gives
// the model's curve at state 0, which ProjectOntoCubic also gives for a model cubic in T.
TEST(StaticCubicByTemperature, RemovesTheModelsDynamicPart) {
  const SimulatedRun run = export_test::ChamberRun(82);
  const DriftModel m = export_test::Fit(run, DriftModelKind::kPolynomial, DriftInputSet::kTempAndRate);
  ASSERT_NE(m.inputs, DriftInputSet::kTemp);
  auto pred = m.Predict({run.temp_c, run.fs_hz});
  ASSERT_TRUE(pred.ok());
  auto c = FitStaticCubicByTemperature(m, {run.temp_c, run.fs_hz}, *pred);
  ASSERT_TRUE(c.ok());
  CubicProjectionOptions po;
  po.temp_min_c = c->temp_min_c, po.temp_max_c = c->temp_max_c, po.ref_temp_c = c->ref_temp_c;
  auto p = ProjectOntoCubic(m, po);
  ASSERT_TRUE(p.ok());
  for (double t = c->temp_min_c; t <= c->temp_max_c; t += 0.5) EXPECT_NEAR(c->Evaluate(t), p->Evaluate(t), 1e-7) << t;
}

// Each temperature alike: a long hold at one end counts as one bin. The run: a ramp 0 -> 40 C
// (1 sample per 0.02 C) carrying +0.1 over the static curve, then 10000 samples held at 40 C on
// it. The binned fit sees the ramp's offset everywhere but one bin: its shape is the curve's
// (up to the constant); a fit over every sample bends towards the hold.
TEST(StaticCubicByTemperature, ALongHoldCountsAsOneTemperature) {
  std::vector<double> temp, y;
  for (int i = 0; i <= 2000; ++i) temp.push_back(0.02 * i), y.push_back(Cubic(0.02 * i) + 0.1);
  for (int i = 0; i < 10000; ++i) temp.push_back(40.0), y.push_back(Cubic(40.0));
  // A temperature-only model (fitted elsewhere): its dynamic part is 0, so the data are binned as they are.
  const DriftModel m = export_test::Fit(export_test::ChamberRun(84), DriftModelKind::kPolynomial, DriftInputSet::kTemp);
  ASSERT_EQ(m.inputs, DriftInputSet::kTemp);
  auto c = FitStaticCubicByTemperature(m, {temp, 1.0}, y);
  ASSERT_TRUE(c.ok()) << c.error().message;
  // Shape: c(T) - c(20) vs Cubic(T) - Cubic(20), within 1 % of the ramp's offset.
  for (double t = 0.0; t <= 40.0; t += 1.0)
    EXPECT_NEAR(c->Evaluate(t) - c->Evaluate(20.0), Cubic(t) - Cubic(20.0), 1e-3) << t;
  // A least-squares cubic over every sample is bent by the hold by more than 10x that.
  Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
  Eigen::Vector4d atb = Eigen::Vector4d::Zero();
  for (std::size_t i = 0; i < temp.size(); ++i) {
    const double x = (temp[i] - 20.0) / 20.0;
    const Eigen::Vector4d a(1.0, x, x * x, x * x * x);
    ata += a * a.transpose(), atb += a * y[i];
  }
  const Eigen::Vector4d k = ata.ldlt().solve(atb);
  auto timed = [&](double t) {
    const double x = (t - 20.0) / 20.0;
    return k[0] + k[1] * x + k[2] * x * x + k[3] * x * x * x;
  };
  double worst = 0.0;
  for (double t = 0.0; t <= 40.0; t += 1.0)
    worst = std::max(worst, std::abs(timed(t) - timed(20.0) - (Cubic(t) - Cubic(20.0))));
  EXPECT_GT(worst, 1e-2);
}

TEST(StaticCubicByTemperature, BadInputsAreErrors) {
  const SimulatedRun run = export_test::ChamberRun(83);
  const DriftModel m = export_test::Fit(run, DriftModelKind::kPolynomial, DriftInputSet::kTemp);
  const DriftInputs in{run.temp_c, run.fs_hz};
  EXPECT_FALSE(FitStaticCubicByTemperature(m, in, std::vector<double>(3, 0.0)).ok());
  StaticCubicOptions o;
  o.bins = 2;
  EXPECT_FALSE(FitStaticCubicByTemperature(m, in, run.rate_dps, o).ok());
  // Every sample at one temperature: one bin, not enough for a cubic.
  std::vector<double> flat(100, 25.0);
  StaticCubicOptions r;
  r.temp_min_c = 20.0, r.temp_max_c = 30.0;
  auto e = FitStaticCubicByTemperature(m, {flat, 1.0}, std::vector<double>(100, 0.0), r);
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().message.find("temperature bins hold samples"), std::string::npos);
}

}  // namespace
}  // namespace gyrocomp
