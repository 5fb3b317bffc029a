// What a calibration run identifies (drift_identify.cc Eqs. I-0..I-3): plateau tables
// and few points, the dT/dt gain on heating-only and staircase runs, the excluded terms in the
// model file.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/drift/drift_model.h"

namespace gyrocomp {
namespace {

double IdentifyCubic(double t) {
  const double x = (t - 20.0) / 40.0;
  return 0.02 + 0.05 * x - 0.03 * x * x + 0.01 * x * x * x;
}

bool Excluded(const DriftFitSummary& s, const std::string& term, const std::string& eq) {
  for (const ExcludedTerm& e : s.excluded_terms)
    if (e.term == term && e.reason.find(eq) != std::string::npos && !e.would_identify.empty()) return true;
  return false;
}

// A 25-row plateau-mean table (one row per plateau, 1200 s apart): 22 plateaus cooling 60 -> -20 C,
// then 3 more at the cold end. Before the identifiability tests (Eqs. I-0..I-3) the default model
// failed on it: its thermal-segment CV left the 3 cold rows alone to fit a cubic ("polynomial fit:
// 4 coefficients need at least 4 samples, got 3").
TEST(DriftIdentify, PlateauTableOf25RowsGetsACubicOrLessAndSaysWhy) {
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 0.002);
  std::vector<double> temp, y;
  for (int i = 0; i < 22; ++i) temp.push_back(60.0 - 80.0 * i / 21.0);
  for (double t : {-20.1, -20.0, -20.05}) temp.push_back(t);
  for (double t : temp) y.push_back(IdentifyCubic(t) + noise(rng));
  DriftFitOptions o;  // the default: auto
  auto m = FitDriftModel({temp, 1.0 / 1200.0}, y, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->kind, DriftModelKind::kPolynomial);
  EXPECT_EQ(m->inputs, DriftInputSet::kTemp);
  EXPECT_LE(m->summary.degree, 3);
  EXPECT_NE(m->summary.data_support.find("25 training points"), std::string::npos) << m->summary.data_support;
  EXPECT_NE(m->summary.data_support.find("contiguous blocks instead"), std::string::npos) << m->summary.data_support;
  EXPECT_TRUE(Excluded(m->summary, "dT/dt gain", "Eq. I-0"));
  EXPECT_TRUE(Excluded(m->summary, "kernel", "Eq. I-0"));
  EXPECT_GT(m->summary.drift_span, 0.05);
  // The cubic it fits follows the table: in-sample error near the noise.
  EXPECT_LT(m->summary.train_rmse, 0.004);
  // With its band (Eqs. B-1..B-4): the table's noise (2 mdps a row) through a cubic.
  ASSERT_TRUE(m->band.has_value()) << m->summary.data_support;
  EXPECT_GT(m->band->expected_rms, 0.0005);
  EXPECT_LT(m->band->expected_rms, 0.01);
}

// Fewer points: 13 rows support 2 coefficients, a straight line.
TEST(DriftIdentify, FewerPointsLowerTheDegree) {
  std::vector<double> temp, y;
  for (int i = 0; i < 13; ++i) temp.push_back(60.0 - 80.0 * i / 12.0);
  for (double t : temp) y.push_back(IdentifyCubic(t));
  auto m = FitDriftModel({temp, 1.0 / 1200.0}, y, DriftFitOptions{});
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->summary.degree, 1);
  EXPECT_NE(m->summary.data_support.find("reduced from 3"), std::string::npos) << m->summary.data_support;
}

// A sensor temperature lagging a chamber schedule (first order, 600 s), at 0.2 Hz.
std::vector<double> Lagged(const std::vector<std::pair<double, double>>& breaks, double fs_hz) {
  std::vector<double> temp;
  double sensor = breaks.front().second;
  const double dt = 1.0 / fs_hz;
  for (double t = 0.0; t < breaks.back().first; t += dt) {
    std::size_t j = 1;
    while (j + 1 < breaks.size() && breaks[j].first <= t) ++j;
    const auto [t0, c0] = breaks[j - 1];
    const auto [t1, c1] = breaks[j];
    const double chamber = c0 + (c1 - c0) * std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
    sensor += (chamber - sensor) * (1.0 - std::exp(-dt / 600.0));
    temp.push_back(sensor);
  }
  return temp;
}

// Drift = cubic + 1.5 dT/dt (deg/s per C/s) + white noise.
std::vector<double> Drift(const std::vector<double>& temp, double fs_hz, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.003);
  auto rate = TemperatureRate(temp, fs_hz);
  std::vector<double> y(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) y[i] = IdentifyCubic(temp[i]) + 1.5 * (*rate)[i] + noise(rng);
  return y;
}

// Eq. I-1: a run that only heats (cold hold, one 1 C/min ramp, hot hold) contrasts holds and
// ramps only at its ends: the gain is left out, with the run that would identify it. The same
// drift on a staircase (holds every 10 C, ramps between) keeps it.
TEST(DriftIdentify, RateGainLeftOutOnHeatingOnlyKeptOnStaircase) {
  const double fs = 0.2;
  const std::vector<double> heat = Lagged({{0, -40}, {3600, -40}, {9600, 60}, {13200, 60}}, fs);
  std::vector<std::pair<double, double>> stairs = {{0, 60}, {3600, 60}};
  for (double c = 50; c >= -40; c -= 10) {
    stairs.push_back({stairs.back().first + 600, c});
    stairs.push_back({stairs.back().first + 3600, c});
  }
  const std::vector<double> cool = Lagged(stairs, fs);
  DriftFitOptions o;
  o.auto_select.try_svr = false;
  for (unsigned seed : {1u, 2u, 3u}) {
    auto h = FitDriftModel({heat, fs}, Drift(heat, fs, seed), o);
    ASSERT_TRUE(h.ok()) << h.error().message;
    EXPECT_EQ(h->inputs, DriftInputSet::kTemp) << "seed " << seed;
    EXPECT_TRUE(Excluded(h->summary, "dT/dt gain", "Eq. I-1")) << "seed " << seed;
    auto c = FitDriftModel({cool, fs}, Drift(cool, fs, seed), o);
    ASSERT_TRUE(c.ok()) << c.error().message;
    EXPECT_EQ(c->inputs, DriftInputSet::kTempAndRate) << "seed " << seed << ": " << c->summary.BriefReport();
    EXPECT_FALSE(Excluded(c->summary, "dT/dt gain", "Eq. I-1")) << "seed " << seed;
    // Neither run heats and cools: the memory and the lag are left out (Eq. I-3).
    EXPECT_TRUE(Excluded(c->summary, "memory", "Eq. I-3"));
    EXPECT_TRUE(Excluded(c->summary, "lag tau", "Eq. I-3"));
  }
}

// EnsureTrainablePlan counts distinct temperatures to 1e-3 of the run's range: a cold hold's noisy
// readings are one temperature. A heating run whose sensor still heats at its end has two thermal
// segments (the cold hold, the heating rest); leaving out the heating one leaves the hold alone,
// and a cubic fitted on it extrapolated: the CV RMSE was 2.5e9 deg/s on a simulated run (and the
// band's model-form part the cap, the drift's SD). The plan falls back to contiguous blocks.
TEST(DriftIdentify, SegmentFoldLeavingOnlyANoisyHoldFallsBackToBlocks) {
  const double fs = 0.2;
  std::vector<double> heat = Lagged({{0, -40}, {3600, -40}, {9600, 60}, {10800, 60}}, fs);
  std::mt19937 rng(7);
  std::normal_distribution<double> temp_noise(0.0, 0.02);
  for (double& t : heat) t += temp_noise(rng);
  DriftFitOptions o;
  o.auto_select.try_svr = false;
  auto m = FitDriftModel({heat, fs}, Drift(heat, fs, 1), o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->summary.cv_scheme, DriftCvScheme::kBlocks) << m->summary.data_support;
  EXPECT_NE(m->summary.data_support.find("contiguous blocks instead"), std::string::npos) << m->summary.data_support;
  EXPECT_LT(m->summary.cv_rmse, m->summary.drift_span) << m->summary.BriefReport();
}

// The excluded terms, the points note and the drift span are written into the model file's
// "training" and read back.
TEST(DriftIdentify, ExcludedTermsRoundTripThroughTheModelFile) {
  std::vector<double> temp, y;
  for (int i = 0; i < 25; ++i) temp.push_back(60.0 - 80.0 * i / 24.0);
  for (double t : temp) y.push_back(IdentifyCubic(t));
  auto m = FitDriftModel({temp, 1.0 / 1200.0}, y, DriftFitOptions{});
  ASSERT_TRUE(m.ok()) << m.error().message;
  ASSERT_FALSE(m->summary.excluded_terms.empty());
  auto back = DriftModelFromJson(DriftModelToJson(*m), "mem");
  ASSERT_TRUE(back.ok()) << back.error().message;
  ASSERT_EQ(back->summary.excluded_terms.size(), m->summary.excluded_terms.size());
  for (std::size_t k = 0; k < m->summary.excluded_terms.size(); ++k) {
    EXPECT_EQ(back->summary.excluded_terms[k].term, m->summary.excluded_terms[k].term);
    EXPECT_EQ(back->summary.excluded_terms[k].reason, m->summary.excluded_terms[k].reason);
    EXPECT_EQ(back->summary.excluded_terms[k].would_identify, m->summary.excluded_terms[k].would_identify);
  }
  EXPECT_EQ(back->summary.data_support, m->summary.data_support);
  EXPECT_EQ(back->summary.drift_span, m->summary.drift_span);
  EXPECT_NE(m->summary.BriefReport().find("left out: dT/dt gain"), std::string::npos);
}

}  // namespace
}  // namespace gyrocomp
