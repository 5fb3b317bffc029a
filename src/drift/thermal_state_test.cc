#include "gyrocomp/drift/thermal_state.h"

#include <cmath>

#include <gtest/gtest.h>

#include "gyrocomp/drift/drift_model.h"

namespace gyrocomp {
namespace {

// A ramp T = T0 + s t after a hold: the lag state tends to T - T_lag = s tau (1 - exp(-t/tau))
// (closed form of a first-order lag of a ramp started from rest), the causal rate to s.
TEST(ThermalState, LagAndCausalRateOnARampMatchClosedForm) {
  const double fs_hz = 2.0, s = 0.01, tau = 300.0;
  std::vector<double> temp(static_cast<std::size_t>(4 * 3600 * fs_hz));
  for (std::size_t i = 0; i < temp.size(); ++i) temp[i] = 20.0 + s * static_cast<double>(i) / fs_hz;
  ThermalStateOptions o;
  o.lag_tau_s = tau;
  auto lag = ComputeThermalState(temp, fs_hz, DriftInputSet::kTempAndLag, {}, o, false);
  ASSERT_TRUE(lag.ok());
  for (std::size_t i : {std::size_t{200}, std::size_t{2000}, temp.size() - 1}) {
    const double t = static_cast<double>(i) / fs_hz;
    // The discrete lag (exact for a held input) lags a ramp by s dt / 2 more than the continuous
    // one: bound 1e-9 + s / fs.
    EXPECT_NEAR((*lag)[i], s * tau * (1.0 - std::exp(-t / tau)), s / fs_hz) << i;
  }
  auto rate = ComputeThermalState(temp, fs_hz, DriftInputSet::kTempAndRate, {}, o, true);
  ASSERT_TRUE(rate.ok());
  // Two cascaded lags of 75 s: after 20 tau the transient is e^-20 ~ 2e-9 of s.
  EXPECT_NEAR(rate->back(), s, 1e-6 * s);
}

// The batch state is exactly the one-sample update (what firmware runs), and the drift model's
// causal prediction is exactly DriftEvaluator::Step.
TEST(ThermalState, BatchEqualsStepAndEvaluatorEqualsCausalPredict) {
  const double fs_hz = 1.0;
  std::vector<double> temp(7200), y(7200);
  for (std::size_t i = 0; i < temp.size(); ++i) {
    const double t = static_cast<double>(i);
    temp[i] = 20.0 + 30.0 * std::sin(t / 900.0) + 0.01 * std::sin(7.0 * t);
    y[i] = 1e-3 * temp[i] + 2e-4 * std::cos(t / 900.0);
  }
  for (DriftInputSet in : {DriftInputSet::kTempAndRate, DriftInputSet::kTempAndLag, DriftInputSet::kTempAndMemory,
                           DriftInputSet::kTempRateAndMemory}) {
    ThermalStateOptions o;
    auto batch = ComputeThermalState(temp, fs_hz, in, {}, o, true);
    ASSERT_TRUE(batch.ok());
    auto memory = ComputeThermalState(temp, fs_hz, DriftInputSet::kTempAndMemory, {}, o, true);
    ASSERT_TRUE(memory.ok());
    ThermalStateEvaluator ev(in, o);
    for (std::size_t i = 0; i < temp.size(); ++i) {
      ASSERT_EQ((*batch)[i], ev.Step(1.0 / fs_hz, temp[i])) << i;
      // temp,dtemp,memory: its second state is the memory of Eq. TS-3, from the same lags.
      if (HasSecondMemoryState(in)) {
        ASSERT_EQ((*memory)[i], ev.memory()) << i;
      }
    }

    DriftFitOptions f;
    f.model = DriftModelKind::kHybrid;
    f.inputs = in;
    f.fit_lag_tau = false;
    f.search.cuckoo.num_nests = 4;
    f.search.cuckoo.max_generations = 1;
    auto m = FitDriftModel({temp, fs_hz}, y, f);
    ASSERT_TRUE(m.ok()) << m.error().message;
    auto causal = m->Predict({temp, fs_hz}, /*causal=*/true);
    ASSERT_TRUE(causal.ok());
    DriftEvaluator de(*m);
    for (std::size_t i = 0; i < temp.size(); ++i) ASSERT_EQ((*causal)[i], de.Step(1.0 / fs_hz, temp[i])) << i;
  }
}

// Memory: +1 after heating by several widths, -1 after cooling, held during a hold.
TEST(ThermalState, MemoryRemembersTheLastDirection) {
  const double fs_hz = 1.0;
  std::vector<double> temp;
  for (int i = 0; i < 3000; ++i) temp.push_back(0.0 + 0.02 * i);         // heat 60 C
  for (int i = 0; i < 3000; ++i) temp.push_back(60.0);                   // hold
  for (int i = 0; i < 3000; ++i) temp.push_back(60.0 - 0.02 * i);        // cool 60 C
  ThermalStateOptions o;
  auto m = ComputeThermalState(temp, fs_hz, DriftInputSet::kTempAndMemory, {}, o, true);
  ASSERT_TRUE(m.ok());
  EXPECT_GT((*m)[2999], 0.99);
  EXPECT_GT((*m)[5999], 0.99);  // held through the hold
  EXPECT_LT((*m)[8999], -0.99);
}

}  // namespace
}  // namespace gyrocomp
