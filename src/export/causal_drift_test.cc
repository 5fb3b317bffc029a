// Causal drift prediction (the thermal states of docs/explanation/drift-models.md,
// DriftModel::Predict(causal = true)) as the exporters see it: equality with the centred prediction
// where no state is read, the shared out-of-range policy, the delay reported.
#include "gyrocomp/export/causal_drift.h"

#include <cmath>

#include <gtest/gtest.h>

#include "export_test_models.h"

namespace gyrocomp {
namespace {

using export_test::ChamberRun;
using export_test::Fit;

// Temperature-only model: the causal prediction IS the centred one; with the clamp policy the
// temperature is clamped to the fitted range (the value at the nearest end), and counted.
TEST(PredictDriftCausal, TemperatureOnlyEqualsModelAndClampPolicy) {
  const SimulatedRun run = ChamberRun(3);
  for (DriftModelKind kind : {DriftModelKind::kPolynomial, DriftModelKind::kSvr}) {
    DriftModel m = Fit(run, kind, DriftInputSet::kTemp, 5);
    std::vector<double> temp = {m.summary.temp_min_c, 0.0, 20.0, m.summary.temp_max_c};
    auto centred = m.Predict(DriftInputs{temp, 1.0});
    auto causal = PredictDriftCausal(m, DriftInputs{temp, 1.0});
    ASSERT_TRUE(centred.ok() && causal.ok());
    for (std::size_t i = 0; i < temp.size(); ++i) EXPECT_EQ((*causal)[i], (*centred)[i]);
    m.out_of_range = OutOfRangePolicy::kClamp;
    std::vector<double> outside = {m.summary.temp_min_c - 10.0, m.summary.temp_max_c + 10.0};
    CausalPredictionSummary s;
    auto clamped = PredictDriftCausal(m, DriftInputs{outside, 1.0}, &s);
    ASSERT_TRUE(clamped.ok());
    EXPECT_EQ((*clamped)[0], (*centred)[0]);
    EXPECT_EQ((*clamped)[1], (*centred)[3]);
    EXPECT_EQ(s.num_clamped, 2u);
    EXPECT_EQ(s.delay_s, 0.0);
  }
}

// A rate model: the delay is two discrete lags, 2 dt / expm1(dt / tau) = 2 tau - dt + dt^2 / (6 tau) + ...,
// and the prediction is the model function at (T, the causal state of DriftEvaluator).
TEST(PredictDriftCausal, RateModelReportsItsDelay) {
  const SimulatedRun run = ChamberRun(4);
  const DriftModel m = Fit(run, DriftModelKind::kPolynomial, DriftInputSet::kTempAndRate);
  CausalPredictionSummary s;
  auto causal = PredictDriftCausal(m, DriftInputs{run.temp_c, run.fs_hz}, &s);
  ASSERT_TRUE(causal.ok());
  const double tau = m.state.causal_rate_tau_s;
  EXPECT_NEAR(s.delay_s, 2.0 * tau - 1.0 + 1.0 / (6.0 * tau), 1e-6);  // dt = 1 s: 2 tau - dt + dt^2 / (6 tau) + O(dt^4)
  DriftEvaluator ev(m);
  for (std::size_t i = 0; i < run.temp_c.size(); ++i) {
    const double e = ev.Step(1.0, run.temp_c[i]);
    if (i % 997 == 0) {
      EXPECT_EQ((*causal)[i], e) << i;
    }
  }
}

}  // namespace
}  // namespace gyrocomp
