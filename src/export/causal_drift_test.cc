// Causal dT/dt and causal drift prediction: closed forms of the double lag, clamping, and the
// equality with the model's own formula.
#include "gyrocomp/export/causal_drift.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "export_test_models.h"

namespace gyrocomp {
namespace {

using export_test::ChamberRun;
using export_test::Fit;

// A ramp T = T0 + s t: after the start-up transient the estimate is s exactly (the backward-Euler
// lag of a ramp is exactly tau at any dt; causal_drift.h). Tolerance: rounding of ~1e5 steps on
// numbers ~50 C, relative 1e-9 of s.
TEST(CausalRate, RampIsExactAfterTransient) {
  for (double dt : {0.01, 0.2, 1.0, 7.0}) {
    for (double slope : {0.05, -0.003}) {
      const double tau = 80.0;
      CausalRateState st;
      double est = 0.0;
      const int n = static_cast<int>(60.0 * tau / dt);
      for (int k = 0; k < n; ++k) est = CausalRateStep(&st, dt, 20.0 + slope * k * dt, tau);
      EXPECT_NEAR(est, slope, 1e-9 * std::abs(slope)) << "dt = " << dt;
    }
  }
}

// A parabola T = c t^2: in steady state the estimate is 2 c (t - 2 tau - dt/2): the delay is
// 2 tau plus half a step from the discretisation (derivation in docs/export.md).
TEST(CausalRate, ParabolaShowsTheDelay) {
  for (double dt : {0.1, 1.0, 5.0}) {
    const double tau = 50.0, c = 1e-5;
    CausalRateState st;
    double est = 0.0, t = 0.0;
    const int n = static_cast<int>(80.0 * tau / dt);
    for (int k = 0; k < n; ++k) {
      t = k * dt;
      est = CausalRateStep(&st, dt, c * t * t, tau);
    }
    const double expected = 2.0 * c * (t - 2.0 * tau - dt / 2.0);
    EXPECT_NEAR(est, expected, 1e-9 * std::abs(expected)) << "dt = " << dt;
  }
}

// The vector form equals the step form and starts at 0; default tau = window / 48^(1/3).
TEST(CausalRate, VectorEqualsSteps) {
  std::vector<double> temp;
  for (int i = 0; i < 500; ++i) temp.push_back(25.0 + 3.0 * std::sin(i / 40.0));
  auto r = CausalTemperatureRate(temp, 2.0, 30.0);
  ASSERT_TRUE(r.ok());
  CausalRateState st;
  for (std::size_t i = 0; i < temp.size(); ++i) EXPECT_EQ((*r)[i], CausalRateStep(&st, 0.5, temp[i], 30.0));
  EXPECT_EQ((*r)[0], 0.0);
  TemperatureRateOptions w;
  w.window_s = 300.0;
  EXPECT_NEAR(ResolvedCausalTau({}, w), 300.0 / std::cbrt(48.0), 1e-12);
  EXPECT_EQ(ResolvedCausalTau(CausalRateOptions{12.0}, w), 12.0);
  EXPECT_FALSE(CausalTemperatureRate({}, 1.0, 1.0).ok());
  std::vector<double> bad = {1.0, NAN};
  EXPECT_FALSE(CausalTemperatureRate(bad, 1.0, 1.0).ok());
  EXPECT_FALSE(CausalTemperatureRate(temp, 0.0, 1.0).ok());
}

// The noise-matching default: for white temperature noise the causal estimate's SD equals the
// centred window's (both formulas in causal_drift.h / temperature_rate.h), measured on 2e5
// samples: the two SDs agree within 5 % (sampling error of an SD over ~2e5 / (tau fs)
// correlated blocks is ~2 %).
TEST(CausalRate, DefaultTauMatchesCentredNoise) {
  const double fs = 10.0, sd = 0.05;
  std::vector<double> temp(200000);
  std::mt19937_64 gen(7);
  std::normal_distribution<double> noise(0.0, sd);
  for (double& t : temp) t = 30.0 + noise(gen);
  TemperatureRateOptions w;
  w.window_s = 60.0;
  auto centred = TemperatureRate(temp, fs, w);
  auto causal = CausalTemperatureRate(temp, fs, ResolvedCausalTau({}, w));
  ASSERT_TRUE(centred.ok() && causal.ok());
  auto sdev = [](const std::vector<double>& v, std::size_t from) {
    double s = 0, ss = 0;
    for (std::size_t i = from; i < v.size() - from; ++i) s += v[i], ss += v[i] * v[i];
    const double n = static_cast<double>(v.size() - 2 * from);
    return std::sqrt(ss / n - (s / n) * (s / n));
  };
  const double a = sdev(*centred, 2000), b = sdev(*causal, 2000);
  EXPECT_NEAR(b / a, 1.0, 0.05) << "centred " << a << ", causal " << b;
}

// Temperature-only model: the causal prediction IS the model's prediction inside the fitted
// range (no estimator involved), and is clamped outside it: the value at the nearest end.
TEST(PredictDriftCausal, TemperatureOnlyEqualsModelAndClamps) {
  const SimulatedRun run = ChamberRun(3);
  for (DriftModelKind kind : {DriftModelKind::kPolynomial, DriftModelKind::kSvr}) {
    const DriftModel m = Fit(run, kind, DriftInputSet::kTemp, 5);
    std::vector<double> temp = {m.summary.temp_min_c, 0.0, 20.0, m.summary.temp_max_c};
    auto centred = m.Predict(DriftInputs{temp, 1.0});
    auto causal = PredictDriftCausal(m, DriftInputs{temp, 1.0});
    ASSERT_TRUE(centred.ok() && causal.ok());
    for (std::size_t i = 0; i < temp.size(); ++i) EXPECT_EQ((*causal)[i], (*centred)[i]);
    std::vector<double> outside = {m.summary.temp_min_c - 10.0, m.summary.temp_max_c + 10.0};
    CausalPredictionSummary s;
    auto clamped = PredictDriftCausal(m, DriftInputs{outside, 1.0}, {}, &s);
    ASSERT_TRUE(clamped.ok());
    EXPECT_EQ((*clamped)[0], (*centred)[0]);
    EXPECT_EQ((*clamped)[1], (*centred)[3]);
    EXPECT_EQ(s.num_clamped, 2u);
    EXPECT_FALSE(s.uses_rate);
    EXPECT_EQ(s.delay_s, 0.0);
  }
}

// Temperature + dT/dt: the prediction is the model's formula at (T, clamp(causal dT/dt)).
TEST(PredictDriftCausal, RateModelUsesTheCausalEstimate) {
  const SimulatedRun run = ChamberRun(4);
  for (DriftModelKind kind : {DriftModelKind::kPolynomial, DriftModelKind::kSvr}) {
    const DriftModel m = Fit(run, kind, DriftInputSet::kTempAndRate);
    CausalPredictionSummary s;
    auto causal = PredictDriftCausal(m, DriftInputs{run.temp_c, run.fs_hz}, {}, &s);
    ASSERT_TRUE(causal.ok());
    const double tau = ResolvedCausalTau({}, m.rate);
    EXPECT_TRUE(s.uses_rate);
    EXPECT_DOUBLE_EQ(s.delay_s, 2.0 * tau);
    auto r = CausalTemperatureRate(run.temp_c, run.fs_hz, tau);
    ASSERT_TRUE(r.ok());
    for (std::size_t i = 0; i < run.temp_c.size(); i += 997) {
      const double rc = std::clamp((*r)[i], m.summary.dtemp_min_c_per_s, m.summary.dtemp_max_c_per_s);
      EXPECT_EQ((*causal)[i], EvaluateDriftModel(m, run.temp_c[i], rc)) << i;
    }
  }
}

}  // namespace
}  // namespace gyrocomp
