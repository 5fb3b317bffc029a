// --static-weight auto: the per-axis choice of the static-curve estimator (static_weight.h).
#include "gyrocomp/export/static_weight.h"

#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/drift/noise_model.h"
#include "gyrocomp/drift/temperature_rate.h"
#include "gyrocomp/export/static_cubic.h"

namespace gyrocomp {
namespace {

double WeightCubic(double t) {
  const double d = t - 25.0;
  return 0.02 + 1.5e-3 * d + 1.2e-5 * d * d - 2.0e-7 * d * d * d;
}

// A chamber heating run as the bench's calibration: 10 min at 10 C, 1 C/min to 60 C, 20 min at
// 60 C, 1 Hz; values = cubic + rate_gain x dT/dt + white noise (deg/s).
struct ChamberHeat {
  std::vector<double> temp_c, y;
};
ChamberHeat HeatingRun(double rate_gain, double noise_sd, unsigned seed) {
  ChamberHeat r;
  for (int i = 0; i < 600; ++i) r.temp_c.push_back(10.0);
  for (int i = 1; i <= 3000; ++i) r.temp_c.push_back(10.0 + i / 60.0);
  for (int i = 0; i < 1200; ++i) r.temp_c.push_back(60.0);
  auto rate = TemperatureRate(r.temp_c, 1.0);
  EXPECT_TRUE(rate.ok());
  std::mt19937 gen(seed);
  std::normal_distribution<double> n(0.0, noise_sd);
  for (std::size_t i = 0; i < r.temp_c.size(); ++i) r.y.push_back(WeightCubic(r.temp_c[i]) + rate_gain * (*rate)[i] + n(gen));
  return r;
}

DriftModel FitAuto(const ChamberHeat& r) {
  auto m = FitDriftModel(DriftInputs{r.temp_c, 1.0}, r.y, DriftFitOptions{});
  EXPECT_TRUE(m.ok()) << (m.ok() ? "" : m.error().message);
  return std::move(*m);
}

TEST(StaticWeight, NamesRoundTrip) {
  for (StaticWeight w : {StaticWeight::kTemperature, StaticWeight::kTime, StaticWeight::kAuto})
    EXPECT_EQ(ParseStaticWeight(StaticWeightName(w)), w);
  EXPECT_FALSE(ParseStaticWeight("bins").has_value());
}

// A cubic-only run (no rate term): no gain part, and the time estimator, which keeps the holds'
// samples, has the lower noise: time.
TEST(StaticWeight, ACubicOnlyRunPicksTime) {
  const ChamberHeat r = HeatingRun(0.0, 0.01, 1);
  const DriftModel m = FitAuto(r);
  ASSERT_EQ(m.inputs, DriftInputSet::kTemp);
  ASSERT_TRUE(m.band.has_value());
  auto c = ChooseStaticWeight(m, {r.temp_c, 1.0}, 10.0, 60.0, CubicCondition::kSteady);
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(c->chosen, StaticWeight::kTime) << c->reason;
  EXPECT_LT(c->time.noise_rms, c->temperature.noise_rms);
  EXPECT_GT(c->time.noise_rms, 0.0);
}

// A strong rate term the heating-only run cannot identify (auto leaves the gain out): the time
// estimator's cubic bends with the ramp's offset, the temperature one absorbs it as a constant.
TEST(StaticWeight, AStrongRateTermPicksTemperature) {
  const ChamberHeat r = HeatingRun(3.0, 0.01, 2);
  const DriftModel m = FitAuto(r);
  ASSERT_EQ(m.inputs, DriftInputSet::kTemp) << "the gain was identified: the test needs it left out";
  ASSERT_TRUE(m.summary.unidentified_rate_gain.has_value());
  auto c = ChooseStaticWeight(m, {r.temp_c, 1.0}, 10.0, 60.0, CubicCondition::kSteady);
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(c->chosen, StaticWeight::kTemperature) << c->reason;
  EXPECT_GT(c->rate_gain_rms, 0.0);
  EXPECT_GT(c->time.rate_gain_rms, 2.0 * c->temperature.rate_gain_rms);
}

// The gain used is the unbiased g^2 - SE^2, not the band's G^2 = g^2: a gain within its SE
// counts as none; one well above it counts (capped by the band's G).
TEST(StaticWeight, GainWithinItsStandardErrorCountsAsNone) {
  const ChamberHeat r = HeatingRun(0.0, 0.01, 3);
  DriftModel m = FitAuto(r);
  m.summary.unidentified_rate_gain = 0.5, m.summary.unidentified_rate_gain_se = 0.6;
  m.band->unidentified_rate_gain_rms = std::hypot(0.5, 0.6);
  auto weak = ChooseStaticWeight(m, {r.temp_c, 1.0}, 10.0, 60.0, CubicCondition::kSteady);
  ASSERT_TRUE(weak.ok());
  EXPECT_EQ(weak->rate_gain_rms, 0.0);
  EXPECT_EQ(weak->chosen, StaticWeight::kTime);
  m.summary.unidentified_rate_gain = 3.0, m.summary.unidentified_rate_gain_se = 0.3;
  m.band->unidentified_rate_gain_rms = std::hypot(3.0, 0.3);
  auto strong = ChooseStaticWeight(m, {r.temp_c, 1.0}, 10.0, 60.0, CubicCondition::kSteady);
  ASSERT_TRUE(strong.ok());
  EXPECT_NEAR(strong->rate_gain_rms, std::sqrt(9.0 - 0.09), 1e-12);
  EXPECT_EQ(strong->chosen, StaticWeight::kTemperature) << strong->reason;
  // A model file keeps only the band's G: then that.
  m.summary.unidentified_rate_gain.reset(), m.summary.unidentified_rate_gain_se.reset();
  auto from_file = ChooseStaticWeight(m, {r.temp_c, 1.0}, 10.0, 60.0, CubicCondition::kSteady);
  ASSERT_TRUE(from_file.ok());
  EXPECT_DOUBLE_EQ(from_file->rate_gain_rms, std::hypot(3.0, 0.3));
}

// The noise part against a Monte Carlo of the two estimators on white noise alone.
TEST(StaticWeight, NoisePartMatchesMonteCarloOnWhiteNoise) {
  const ChamberHeat r = HeatingRun(0.0, 0.01, 4);
  DriftModel m = FitAuto(r);
  m.band->noise = NoisePsd{2.0 * 0.01 * 0.01 / 1.0, 0.0, 0.0};  // var = h0 fs / 2 = 1e-4
  m.summary.unidentified_rate_gain = 0.0, m.summary.unidentified_rate_gain_se = 1.0;
  auto c = ChooseStaticWeight(m, {r.temp_c, 1.0}, 10.0, 60.0, CubicCondition::kSteady);
  ASSERT_TRUE(c.ok());
  // Monte Carlo: the centred RMS over the range of each estimator's cubic fitted on pure noise.
  std::mt19937 gen(5);
  std::normal_distribution<double> n(0.0, 0.01);
  double ss_time = 0.0, ss_temp = 0.0;
  constexpr int kTrials = 300;
  for (int t = 0; t < kTrials; ++t) {
    std::vector<double> y(r.temp_c.size());
    for (double& v : y) v = n(gen);
    auto time = FitDriftModel(DriftInputs{r.temp_c, 1.0}, y, [] {
      DriftFitOptions o;
      o.model = DriftModelKind::kPolynomial, o.inputs = DriftInputSet::kTemp, o.polynomial.degree = 3, o.band = false;
      return o;
    }());
    ASSERT_TRUE(time.ok());
    StaticCubicOptions so;
    so.temp_min_c = 10.0, so.temp_max_c = 60.0;
    auto temp = FitStaticCubicByTemperature(*time, {r.temp_c, 1.0}, y, so);
    ASSERT_TRUE(temp.ok());
    double mt = 0.0, mp = 0.0, st = 0.0, sp = 0.0;
    for (int i = 0; i <= 400; ++i) {
      const double tc = 10.0 + 50.0 * i / 400.0;
      const double a = time->PredictAt(tc, 0.0), b = temp->Evaluate(tc);
      mt += a / 401.0, mp += b / 401.0, st += a * a / 401.0, sp += b * b / 401.0;
    }
    ss_time += (st - mt * mt) / kTrials, ss_temp += (sp - mp * mp) / kTrials;
  }
  EXPECT_NEAR(c->time.noise_rms, std::sqrt(ss_time), 0.15 * std::sqrt(ss_time));
  EXPECT_NEAR(c->temperature.noise_rms, std::sqrt(ss_temp), 0.15 * std::sqrt(ss_temp));
}

// Several runs: the noise parts fall with the runs, the gain part does not; a choice that is
// time on one run can turn to temperature on three.
StaticEstimatorError Estimator(double shape_c_per_s, double noise, double gain) {
  StaticEstimatorError e;
  e.rate_shape_rms = shape_c_per_s, e.rate_gain_rms = gain * shape_c_per_s, e.noise_rms = noise;
  e.total_rms = std::hypot(e.rate_gain_rms, noise);
  return e;
}
StaticWeightChoice OneRun(double gain, std::optional<double> g = {}, std::optional<double> se = {}) {
  StaticWeightChoice c;
  c.time = Estimator(1.0e-4, 2.0e-4, gain);
  c.temperature = Estimator(0.3e-4, 2.4e-4, gain);
  c.rate_gain_rms = gain, c.band_gain_rms = 10.0, c.gain = g, c.gain_se = se;
  return c;
}

TEST(StaticWeight, CombinedRunsWeighTheGainMore) {
  const StaticWeightChoice one = OneRun(1.0);
  ASSERT_LT(one.time.total_rms, one.temperature.total_rms);
  const StaticWeightChoice single = CombineStaticWeightChoices({one});
  EXPECT_EQ(single.chosen, StaticWeight::kTime);
  const StaticWeightChoice three = CombineStaticWeightChoices({one, one, one});
  EXPECT_EQ(three.chosen, StaticWeight::kTemperature) << three.reason;
  EXPECT_NEAR(three.time.noise_rms, 2.0e-4 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(three.time.rate_gain_rms, 1.0e-4, 1e-12);
}

// With the runs' gains and SEs the gain is estimated from all runs: gains that agree add up,
// gains that disagree (noise) cancel.
TEST(StaticWeight, CombinedRunsEstimateOneGain) {
  const double g1 = std::sqrt(1.0 - 0.25);  // each run: sqrt(g^2 - SE^2) of g 1, SE 0.5
  const StaticWeightChoice agree =
      CombineStaticWeightChoices({OneRun(g1, 1.0, 0.5), OneRun(g1, 1.0, 0.5), OneRun(g1, 1.0, 0.5)});
  EXPECT_NEAR(*agree.gain, 1.0, 1e-12);
  EXPECT_NEAR(agree.rate_gain_rms, std::sqrt(1.0 - 0.25 / 3.0), 1e-12);
  EXPECT_EQ(agree.chosen, StaticWeight::kTemperature) << agree.reason;
  const StaticWeightChoice disagree =
      CombineStaticWeightChoices({OneRun(g1, 1.0, 0.5), OneRun(g1, -1.0, 0.5), OneRun(g1, 1.0, 0.5)});
  EXPECT_NEAR(disagree.rate_gain_rms, std::sqrt(1.0 / 9.0 - 0.25 / 3.0), 1e-12);
  EXPECT_EQ(disagree.chosen, StaticWeight::kTime) << disagree.reason;
}

TEST(StaticWeight, BadInputsAreErrors) {
  const ChamberHeat r = HeatingRun(0.0, 0.01, 6);
  DriftModel m = FitAuto(r);
  const DriftInputs in{r.temp_c, 1.0};
  EXPECT_FALSE(ChooseStaticWeight(m, in, 30.0, 30.0, CubicCondition::kSteady).ok());
  StaticWeightOptions o;
  o.bins = 2;
  EXPECT_FALSE(ChooseStaticWeight(m, in, 10.0, 60.0, CubicCondition::kSteady, o).ok());
  o = {};
  o.red_block_s = 0.0;
  EXPECT_FALSE(ChooseStaticWeight(m, in, 10.0, 60.0, CubicCondition::kSteady, o).ok());
  m.band.reset();
  auto e = ChooseStaticWeight(m, in, 10.0, 60.0, CubicCondition::kSteady);
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().message.find("no prediction band"), std::string::npos);
}

}  // namespace
}  // namespace gyrocomp
