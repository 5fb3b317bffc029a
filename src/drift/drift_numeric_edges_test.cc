// Numbers at the edges of the double range in the drift stage (each case a crash class
// found by fuzz/fuzz_numeric_drift.cc) and the option bounds that keep a fit loadable.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/decompose/vmd.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/drift/noise_model.h"
#include "gyrocomp/drift/svr.h"
#include "gyrocomp/drift/thermal_state.h"

namespace gyrocomp {
namespace {

std::vector<double> Alternating(std::size_t n, double amplitude) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = (i % 2 ? 1.0 : -1.0) * amplitude;
  return x;
}

std::vector<double> Ramp(std::size_t n, double from, double to) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = from + (to - from) * static_cast<double>(i) / static_cast<double>(n - 1);
  return x;
}

// A +-1.8e308 target gave a training RMSE of inf: the model was written with null and refused at
// load. What fit returns, a model file must hold.
TEST(DriftNumericEdges, FitOfAnUnrepresentableTargetIsRefusedNotWrittenUnloadable) {
  const std::vector<double> temp = Ramp(104, 20.0, 40.0);
  const std::vector<double> target = Alternating(104, std::numeric_limits<double>::max());
  for (DriftModelKind kind : {DriftModelKind::kPolynomial, DriftModelKind::kSvr}) {
    DriftFitOptions o;
    o.model = kind;
    o.cv_folds = 2;
    const Result<DriftModel> m = FitDriftModel(DriftInputs{temp, 0.2}, target, o);
    if (!m.ok()) {
      EXPECT_FALSE(m.error().message.empty());
      continue;
    }
    DriftModelSet set;
    set.axes.push_back(*m);
    const auto back = DriftModelSetFromJson(DriftModelSetToJson(set), "m.json");
    EXPECT_TRUE(back.ok()) << back.error().message;
  }
}

// +-1.8e308 C gave a causal rate of -inf with a success status.
TEST(DriftNumericEdges, ThermalStateRefusesTemperaturesNoLogHolds) {
  const std::vector<double> temp = Alternating(55, std::numeric_limits<double>::max());
  for (DriftInputSet inputs : {DriftInputSet::kTempAndRate, DriftInputSet::kTempAndLag, DriftInputSet::kTempAndMemory}) {
    for (bool causal : {false, true}) {
      const auto s = ComputeThermalState(temp, 5.0, inputs, TemperatureRateOptions{}, ThermalStateOptions{}, causal);
      ASSERT_FALSE(s.ok());
      EXPECT_NE(s.error().message.find("must be in [-273.15, 1000] C"), std::string::npos) << s.error().message;
    }
  }
  const auto ok = ComputeThermalState(Ramp(55, -40.0, 85.0), 5.0, DriftInputSet::kTempAndLag, TemperatureRateOptions{},
                                      ThermalStateOptions{}, true);
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  for (double v : *ok) EXPECT_TRUE(std::isfinite(v));
}

// Values of 1e153 gave noise coefficients whose block-mean autocovariance was inf.
TEST(DriftNumericEdges, NoiseModelRefusesValuesWhoseSquaresLeaveTheModelRange) {
  std::vector<double> x = Alternating(151, 1.0);
  x[7] = -1e153;
  const auto psd = FitNoisePsd(x, 5.0);
  ASSERT_FALSE(psd.ok());
  EXPECT_NE(psd.error().message.find("beyond 1e40"), std::string::npos) << psd.error().message;
}

// fit --model svr --gamma 1e300 (also --epsilon, --C) exited 0 with a model apply refused.
TEST(DriftNumericEdges, SvrOptionsAreBoundedSoThatTheModelLoads) {
  std::string why;
  SvrOptions o;
  o.gamma = 1e300;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("(0, 1e6]"), std::string::npos) << why;
  o = SvrOptions{};
  o.epsilon = 1e300;
  EXPECT_FALSE(o.IsValid(&why));
  o = SvrOptions{};
  o.C = 1e300;
  EXPECT_FALSE(o.IsValid(&why));
  o = SvrOptions{};
  o.sigma = 1e-9;
  EXPECT_FALSE(o.IsValid(&why));
  o = SvrOptions{};
  o.C = SvrOptions::kMaxC;
  o.gamma = SvrOptions::kMaxGamma;
  o.epsilon = SvrOptions::kMaxEpsilon;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  SvrSearchOptions s;
  s.C.upper = 1e9;
  EXPECT_FALSE(s.IsValid(&why));
  EXPECT_NE(why.find("(0, 1e6]"), std::string::npos) << why;
}

// decompose --tau 1e300 drove VMD to NaN; only the JSON writer stopped it.
TEST(DriftNumericEdges, VmdTauIsBoundedByItsDivergence) {
  std::string why;
  VmdOptions o;
  o.tau = 1e300;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("[0, 2]"), std::string::npos) << why;
  o.tau = VmdOptions::kMaxTau;
  EXPECT_TRUE(o.IsValid(&why)) << why;
}

}  // namespace
}  // namespace gyrocomp
