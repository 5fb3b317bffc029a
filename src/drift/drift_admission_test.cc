// --model auto's term admission (Eq. A-4, term_admission.h) on simulated runs: every structured
// term is tested against the simpler model it extends, the explanation lists each test, and the
// chosen model carries exactly the admitted terms.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/sim/simulator.h"

namespace gyrocomp {
namespace {

SimulatedRun SimulateRun(ThermalProfileKind kind, std::uint64_t seed, double dtemp_coeff, double hysteresis) {
  SimulatorOptions so;
  so.fs_hz = 1.0;
  so.seed = seed;
  so.profile.kind = kind;
  so.bias.dtemp_coeff_dps_per_c_per_s = dtemp_coeff;
  so.bias.hysteresis_coeff_dps_per_c = hysteresis;
  auto run = Simulate(so);
  EXPECT_TRUE(run.ok()) << run.error().message;
  return std::move(*run);
}

bool Has(const DriftModel& m, const std::string& term) {
  const DriftInputSet in = m.inputs;
  if (term == "dT/dt") return in == DriftInputSet::kTempAndRate || in == DriftInputSet::kTempRateAndMemory;
  if (term == "memory") return in == DriftInputSet::kTempAndMemory || in == DriftInputSet::kTempRateAndMemory;
  const bool gain_in_t = m.summary.gain_temp_degree > 0;
  return in == DriftInputSet::kTempAndLag && (term == "lagged curve" ? gain_in_t : !gain_in_t);
}

// The rule as the fit applies it: dT/dt, tested first against poly(T), enters when Eq. I-1 fitted
// it; a memory or lag is admitted iff gain > SE (>= 2 segments) and is in the model only then; the
// explanation prints each test's gain +- SE.
void ExpectRuleApplied(const DriftModel& m) {
  const DriftFitSummary& s = m.summary;
  ASSERT_GE(s.term_admissions.size(), 3u) << s.selection_reason;
  EXPECT_EQ(s.term_admissions[0].term, "dT/dt");
  EXPECT_EQ(s.term_admissions[0].simpler, "poly(temp)");
  bool rate_admitted = false;
  for (const TermAdmission& t : s.term_admissions) {
    if (t.term == "dT/dt") {
      EXPECT_EQ(t.admitted, t.note.empty()) << t.BriefReport();  // Eq. I-1 decides; A-4 is shown
    } else if (t.term == "kernel") {  // a pure kernel: Eq. H-1, gain > block-to-block SD
      EXPECT_EQ(t.admitted, t.gain.pairs >= 2 && t.gain.gain > t.gain.Sd()) << t.BriefReport();
      if (!t.admitted) {
        EXPECT_NE(m.kind, t.candidate.rfind("cs-svr", 0) == 0 ? DriftModelKind::kCsSvr : DriftModelKind::kSvr);
      }
      continue;
    } else if (t.gain.pairs >= 2) {
      EXPECT_EQ(t.admitted, t.gain.gain > t.gain.se) << t.BriefReport();
      EXPECT_NE(s.selection_reason.find(t.BriefReport()), std::string::npos) << s.selection_reason;
    } else {
      EXPECT_FALSE(t.admitted) << t.BriefReport();
    }
    if (t.term == "dT/dt") rate_admitted = t.admitted;
    if (!t.admitted && t.term != "dT/dt") {
      EXPECT_FALSE(Has(m, t.term)) << t.BriefReport();
    }
  }
  // A lag admitted over poly(T, dT/dt) replaces the dT/dt term (on a ramp T - T_lag ~ tau dT/dt).
  if (m.inputs != DriftInputSet::kTempAndLag) {
    EXPECT_EQ(Has(m, "dT/dt"), rate_admitted) << s.selection_reason;
  }
}

// A strong dT/dt gain (4 deg/s per C/s) on the paper's cooling staircase: the gain is admitted,
// far beyond its SE; the memory and lag are not tested (one direction: not identified).
TEST(DriftAdmission, AStrongRateGainIsAdmitted) {
  DriftFitOptions o;
  o.auto_select.try_svr = false;
  const SimulatedRun r = SimulateRun(ThermalProfileKind::kPaper, 1, 4.0, 0.0);
  auto m = FitDriftModel({r.temp_c, r.fs_hz}, r.rate_dps, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  ExpectRuleApplied(*m);
  const TermAdmission& rate = m->summary.term_admissions[0];
  EXPECT_TRUE(rate.admitted) << rate.BriefReport();
  EXPECT_GT(rate.gain.pairs, 2u) << rate.BriefReport();
  EXPECT_EQ(m->inputs, DriftInputSet::kTempAndRate) << m->summary.selection_reason;
}

// A run that heats and cools, drift of T and dT/dt only (no hysteresis): the rule holds for
// every tested term, and a term that is not admitted is not in the model.
TEST(DriftAdmission, TwoDirectionRunWithoutMemory) {
  DriftFitOptions o;
  o.auto_select.try_svr = false;
  for (std::uint64_t seed : {1u, 2u}) {
    const SimulatedRun r = SimulateRun(ThermalProfileKind::kHeatCool, seed, 1.5, 0.0);
    auto m = FitDriftModel({r.temp_c, r.fs_hz}, r.rate_dps, o);
    ASSERT_TRUE(m.ok()) << m.error().message;
    std::printf("seed %llu: %s\n", static_cast<unsigned long long>(seed), m->summary.selection_reason.c_str());
    ExpectRuleApplied(*m);
  }
}

// A heat-cool run whose drift is a curve of the temperature seen through a first-order lag of
// tau_s behind the thermometer's (the sensor's true temperature), plus white noise of noise_dps:
// f(T_lag) = 0.02 u + 0.03 u^2 - 0.02 u^3 deg/s, u = (T_lag - 10) / 50.
std::vector<double> LaggedCurveTarget(const SimulatedRun& r, double tau_s, double noise_dps, std::uint32_t seed) {
  std::mt19937 gen(seed);
  std::normal_distribution<double> white(0.0, noise_dps);
  std::vector<double> y(r.num_samples());
  double lag = r.sensor_temp_c[0];
  for (std::size_t i = 0; i < y.size(); ++i) {
    lag += (r.sensor_temp_c[i] - lag) / (tau_s * r.fs_hz);  // explicit Euler of dT_lag/dt = (T - T_lag) / tau
    const double u = (lag - 10.0) / 50.0;
    y[i] = 0.02 * u + 0.03 * u * u - 0.02 * u * u * u + white(gen);
  }
  return y;
}

// The lagged curve (DriftAutoOptions::lagged_curve_gain_degree) on a run whose drift is exactly
// that form, tau 600 s, low noise: Eq. A-4 on segment pieces admits it and the model is
// poly(T) + g(T) (T - T_lag) with the gain in T; the explanation prints its gain +- SE.
TEST(DriftAdmission, ALaggedCurveIsAdmittedWhenTheDriftIsOne) {
  DriftFitOptions o;
  o.auto_select.try_svr = false;
  o.auto_select.lagged_curve_gain_degree = 2;
  const SimulatedRun r = SimulateRun(ThermalProfileKind::kHeatCool, 1, 0.0, 0.0);
  const std::vector<double> y = LaggedCurveTarget(r, 600.0, 2e-4, 1);
  auto m = FitDriftModel({r.temp_c, r.fs_hz}, y, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  ExpectRuleApplied(*m);
  const TermAdmission& t = m->summary.term_admissions.back();
  ASSERT_EQ(t.term, "lagged curve") << m->summary.selection_reason;
  // Pieces: more pairs than the whole-segment tests (3 per segment, fewer only for short ones).
  EXPECT_GT(t.gain.pairs, m->summary.term_admissions[0].gain.pairs) << t.BriefReport();
  EXPECT_TRUE(t.admitted) << t.BriefReport();
  EXPECT_EQ(m->inputs, DriftInputSet::kTempAndLag) << m->summary.selection_reason;
  EXPECT_EQ(m->summary.gain_temp_degree, 2) << m->summary.selection_reason;
  EXPECT_NE(m->summary.selection_reason.find("+lagged curve ("), std::string::npos) << m->summary.selection_reason;
}

// The same run with a drift of T and dT/dt only (no lag, no curvature to read at another
// temperature): the lagged curve is tested and rejected, and the model has no gain in T.
TEST(DriftAdmission, ALaggedCurveIsRejectedWithoutALag) {
  DriftFitOptions o;
  o.auto_select.try_svr = false;
  o.auto_select.lagged_curve_gain_degree = 2;
  const SimulatedRun r = SimulateRun(ThermalProfileKind::kHeatCool, 2, 1.5, 0.0);
  auto m = FitDriftModel({r.temp_c, r.fs_hz}, r.rate_dps, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  ExpectRuleApplied(*m);
  const TermAdmission& t = m->summary.term_admissions.back();
  ASSERT_EQ(t.term, "lagged curve") << m->summary.selection_reason;
  EXPECT_GE(t.gain.pairs, 2u) << t.BriefReport();
  EXPECT_FALSE(t.admitted) << t.BriefReport();
  EXPECT_EQ(m->summary.gain_temp_degree, 0) << m->summary.selection_reason;
}

// Off by default (lagged_curve_gain_degree = 0): no lagged-curve candidate and no test; on a
// one-direction run with it on, the candidate is skipped by Eq. I-3 with the reason.
TEST(DriftAdmission, TheLaggedCurveIsOffByDefaultAndNeedsBothDirections) {
  DriftFitOptions o;
  o.auto_select.try_svr = false;
  const SimulatedRun two = SimulateRun(ThermalProfileKind::kHeatCool, 1, 1.5, 0.0);
  auto m = FitDriftModel({two.temp_c, two.fs_hz}, two.rate_dps, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  for (const TermAdmission& t : m->summary.term_admissions) EXPECT_NE(t.term, "lagged curve");
  o.auto_select.lagged_curve_gain_degree = 2;
  const SimulatedRun one = SimulateRun(ThermalProfileKind::kPaper, 1, 1.5, 0.0);
  m = FitDriftModel({one.temp_c, one.fs_hz}, one.rate_dps, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  const TermAdmission& t = m->summary.term_admissions.back();
  ASSERT_EQ(t.term, "lagged curve") << m->summary.selection_reason;
  EXPECT_FALSE(t.admitted);
  EXPECT_NE(t.note.find("Eq. I-3"), std::string::npos) << t.BriefReport();
}

}  // namespace
}  // namespace gyrocomp
