// The hybrid model (structured part + SVR on its residual) and --model auto.
#include <cmath>
#include <algorithm>
#include <cstdio>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "drift_model_internal.h"
#include "gyrocomp/drift/drift_model.h"

namespace gyrocomp {
namespace {

// Two triangle cycles 60 -> -35 -> 60 C (fs 0.5 Hz, 4 h): both directions over the whole range,
// four ramps (thermal segments).
std::vector<double> Sweep(double fs_hz) {
  const std::size_t n = static_cast<std::size_t>(4 * 3600 * fs_hz);
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double u = std::fmod(2.0 * static_cast<double>(i) / static_cast<double>(n), 1.0);  // 0..1 per cycle
    t[i] = 60.0 - 95.0 * (u < 0.5 ? 2.0 * u : 2.0 - 2.0 * u);
  }
  return t;
}

double Rmse(const std::vector<double>& a, const std::vector<double>& b) {
  double ss = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) ss += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(ss / static_cast<double>(a.size()));
}

// A linear drift plus a narrow bump at 10 C that no cubic can follow. The hybrid learns the
// bump (in-sample error well below the polynomial's), and with the intercept folded into the
// structured constant its kernel part vanishes far from the support: at 500 C the prediction is
// the polynomial's alone.
TEST(DriftModelHybrid, LearnsWhatThePolynomialMissesAndFallsBackToIt) {
  const double fs_hz = 0.5;
  const std::vector<double> temp = Sweep(fs_hz);
  std::vector<double> y(temp.size());
  for (std::size_t i = 0; i < y.size(); ++i)
    y[i] = 1e-3 * temp[i] + 0.02 * std::exp(-(temp[i] - 10.0) * (temp[i] - 10.0) / (2.0 * 4.0 * 4.0));
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  o.polynomial.degree = 3;
  auto poly = FitDriftModel({temp, fs_hz}, y, o);
  o.model = DriftModelKind::kHybrid;
  o.search.cuckoo.num_nests = 8;
  o.search.cuckoo.max_generations = 4;
  auto hybrid = FitDriftModel({temp, fs_hz}, y, o);
  ASSERT_TRUE(poly.ok() && hybrid.ok()) << (hybrid.ok() ? "" : hybrid.error().message);
  ASSERT_TRUE(hybrid->structured && hybrid->kernel);
  EXPECT_NE(hybrid->summary.kernel_decision.find("kernel kept"), std::string::npos) << hybrid->summary.kernel_decision;
  EXPECT_EQ(hybrid->kernel->intercept, 0.0);
  EXPECT_EQ(hybrid->kernel->target_offset, 0.0);
  EXPECT_EQ(hybrid->summary.cv_scheme, DriftCvScheme::kThermalSegments);
  const double e_poly = Rmse(*poly->Predict({temp, fs_hz}), y);
  const double e_hybrid = Rmse(*hybrid->Predict({temp, fs_hz}), y);
  std::printf("in-sample RMSE: poly %.3g, hybrid %.3g\n", e_poly, e_hybrid);
  EXPECT_LT(e_hybrid, 0.25 * e_poly) << e_hybrid << " vs " << e_poly << "\n" << hybrid->summary.BriefReport();
  EXPECT_EQ(hybrid->PredictAt(500.0, 0.0), hybrid->structured->PredictOne(500.0, 0.0));
  // Clamping: at 500 C the clamped model predicts what it does at the fitted maximum.
  DriftModel clamped = *hybrid;
  clamped.out_of_range = OutOfRangePolicy::kClamp;
  EXPECT_EQ(clamped.PredictAt(500.0, 0.0), hybrid->PredictAt(hybrid->temp_max_c(), 0.0));
}

// Slow wander like a gyro's bias instability: AR(1) with a 10 min correlation time, SD sd.
std::vector<double> Wander(std::size_t n, double fs_hz, double sd, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double a = std::exp(-1.0 / (600.0 * fs_hz));
  std::vector<double> w(n);
  double x = sd * normal(rng);
  for (std::size_t i = 0; i < n; ++i) w[i] = x = a * x + sd * std::sqrt(1.0 - a * a) * normal(rng);
  return w;
}

// Eq. H-1: on a drift the cubic represents exactly plus slow wander (the residual is pure
// noise) the hybrid's kernel is dropped and the model is its structured part, the polynomial
// fit itself; with a bump the cubic cannot follow, under the same wander, the kernel is kept.
// Without the test (--keep-kernel) the kernel stays in both cases.
TEST(DriftModelHybrid, KernelDroppedOnNoiseResidualKeptOnStructure) {
  const double fs_hz = 0.5;
  const std::vector<double> temp = Sweep(fs_hz);
  for (unsigned seed : {1u, 2u, 3u}) {
    const std::vector<double> w = Wander(temp.size(), fs_hz, 2e-3, seed);
    std::vector<double> noise_only(temp.size()), bump(temp.size());
    for (std::size_t i = 0; i < temp.size(); ++i) {
      noise_only[i] = 1e-3 * temp[i] + 2e-5 * temp[i] * temp[i] + w[i];
      bump[i] = noise_only[i] + 0.02 * std::exp(-(temp[i] - 10.0) * (temp[i] - 10.0) / (2.0 * 4.0 * 4.0));
    }
    DriftFitOptions o;
    o.polynomial.degree = 3;
    o.model = DriftModelKind::kPolynomial;
    auto poly = FitDriftModel({temp, fs_hz}, noise_only, o);
    o.model = DriftModelKind::kHybrid;
    o.search.cuckoo.num_nests = 8;
    o.search.cuckoo.max_generations = 2;
    auto dropped = FitDriftModel({temp, fs_hz}, noise_only, o);
    auto kept = FitDriftModel({temp, fs_hz}, bump, o);
    o.hybrid_kernel_test = false;
    auto forced = FitDriftModel({temp, fs_hz}, noise_only, o);
    ASSERT_TRUE(poly.ok() && dropped.ok() && kept.ok() && forced.ok());
    EXPECT_EQ(dropped->kind, DriftModelKind::kPolynomial) << "seed " << seed << ": " << dropped->summary.kernel_decision;
    EXPECT_FALSE(dropped->kernel);
    EXPECT_NE(dropped->summary.kernel_decision.find("kernel dropped"), std::string::npos);
    EXPECT_EQ(*dropped->Predict({temp, fs_hz}), *poly->Predict({temp, fs_hz}));
    ASSERT_EQ(dropped->structured->terms.size(), poly->structured->terms.size());
    for (std::size_t k = 0; k < poly->structured->terms.size(); ++k)
      EXPECT_EQ(dropped->structured->terms[k].coefficient, poly->structured->terms[k].coefficient);
    EXPECT_EQ(kept->kind, DriftModelKind::kHybrid) << "seed " << seed << ": " << kept->summary.kernel_decision;
    EXPECT_TRUE(kept->kernel);
    EXPECT_EQ(forced->kind, DriftModelKind::kHybrid);
    EXPECT_TRUE(forced->summary.kernel_decision.empty());
  }
}

// A chamber run like the paper's at fs_hz: 1 h at 25 C, 1 C/min to 60 C, then 10 C steps down to
// -40 C, each held 1 h (the sensor temperature follows the chamber with a 600 s lag).
std::vector<double> PaperLike(double fs_hz) {
  std::vector<std::pair<double, double>> knots = {{0.0, 25.0}, {3600.0, 25.0}, {5700.0, 60.0}, {9300.0, 60.0}};
  for (double t = 9300.0, c = 60.0; c > -40.0; c -= 10.0) {
    knots.push_back({t += 600.0, c - 10.0});
    knots.push_back({t += 3600.0, c - 10.0});
  }
  const std::size_t n = static_cast<std::size_t>(knots.back().first * fs_hz);
  std::vector<double> temp(n);
  double sensor = 25.0;
  const double a = 1.0 - std::exp(-1.0 / (600.0 * fs_hz));
  for (std::size_t i = 0, k = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / fs_hz;
    while (k + 2 < knots.size() && knots[k + 1].first <= t) ++k;
    const double u = knots[k].second + (knots[k + 1].second - knots[k].second) * (t - knots[k].first) /
                                           (knots[k + 1].first - knots[k].first);
    temp[i] = sensor += a * (u - sensor);
  }
  return temp;
}

// Eq. H-1 among structured states (auto, kernels off): on a drift of T and dT/dt under slow
// wander the lag state (whose tau is searched on the CV score) does not replace dT/dt, for three
// seeds; on a drift of a die temperature lagging T by 1500 s it does when the calibration heats
// and cools (two triangle cycles), and is not fitted at all from a paper-like run (one short
// heating leg: a lag is a direction memory there, docs/explanation/drift-models.md "Thermal states"). (On these
// seeds the lowest CV agrees; the rule itself is checked in closed form in
// PairedFoldGainClosedForm, and on the simulated runs of bench/drift_heldout.sh.)
TEST(DriftModelAuto, LagStateReplacesRateOnlyWhenItGainsBeyondItsSpread) {
  const double fs_hz = 0.2;
  const std::vector<double> temp = PaperLike(fs_hz);
  DriftFitOptions o;  // auto
  o.auto_select.try_svr = false;
  for (unsigned seed : {1u, 2u, 3u}) {
    const std::vector<double> w = Wander(temp.size(), fs_hz, 2e-3, seed);
    std::vector<double> y(temp.size());
    for (std::size_t i = 0; i < y.size(); ++i) {
      const std::size_t lo = i > 0 ? i - 1 : 0, hi = std::min(i + 1, y.size() - 1);
      const double rate = (temp[hi] - temp[lo]) * fs_hz / static_cast<double>(hi - lo);
      y[i] = 1e-3 * temp[i] + 2e-5 * temp[i] * temp[i] + 1.5 * rate + w[i];
    }
    auto m = FitDriftModel({temp, fs_hz}, y, o);
    ASSERT_TRUE(m.ok()) << m.error().message;
    std::printf("seed %u: %s\n", seed, m->summary.selection_reason.c_str());
    EXPECT_EQ(m->inputs, DriftInputSet::kTempAndRate) << "seed " << seed << ": " << m->summary.selection_reason;
  }
  // A die lagging the measured temperature by 1500 s.
  auto die_lag = [&](const std::vector<double>& t) {
    std::vector<double> y(t.size());
    double die = t[0];
    const double a = 1.0 - std::exp(-1.0 / (1500.0 * fs_hz));
    const std::vector<double> w = Wander(t.size(), fs_hz, 2e-4, 4);
    for (std::size_t i = 0; i < y.size(); ++i) y[i] = 2e-3 * (die += a * (t[i] - die)) + w[i];
    return y;
  };
  const std::vector<double> sweep = Sweep(fs_hz);
  auto m = FitDriftModel({sweep, fs_hz}, die_lag(sweep), o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->inputs, DriftInputSet::kTempAndLag) << m->summary.selection_reason;
  m = FitDriftModel({temp, fs_hz}, die_lag(temp), o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->inputs, DriftInputSet::kTempAndRate) << m->summary.selection_reason;
  EXPECT_NE(m->summary.selection_reason.find("skipped: the run does not both heat and cool"), std::string::npos)
      << m->summary.selection_reason;
}

// A calibration that cools (and heats once, briefly): Eq. H-1 could only score the kernel on that
// direction, so the hybrid is not searched and is its structured part, even with a bump the cubic
// cannot follow (which a heating-and-cooling sweep keeps, above); --keep-kernel still keeps it.
TEST(DriftModelHybrid, KernelNotSearchedOnARunThatDoesNotHeatAndCool) {
  const double fs_hz = 0.2;
  const std::vector<double> temp = PaperLike(fs_hz);
  std::vector<double> y(temp.size());
  for (std::size_t i = 0; i < y.size(); ++i)
    y[i] = 1e-3 * temp[i] + 0.02 * std::exp(-(temp[i] - 10.0) * (temp[i] - 10.0) / (2.0 * 4.0 * 4.0));
  DriftFitOptions o;
  o.model = DriftModelKind::kHybrid;
  o.search.cuckoo.num_nests = 6;
  o.search.cuckoo.max_generations = 1;
  auto h = FitDriftModel({temp, fs_hz}, y, o);
  ASSERT_TRUE(h.ok()) << h.error().message;
  EXPECT_EQ(h->kind, DriftModelKind::kPolynomial);
  EXPECT_FALSE(h->kernel);
  EXPECT_EQ(h->summary.evaluations, 0);
  EXPECT_NE(h->summary.kernel_decision.find("not searched"), std::string::npos) << h->summary.kernel_decision;
  o.hybrid_kernel_test = false;
  auto forced = FitDriftModel({temp, fs_hz}, y, o);
  ASSERT_TRUE(forced.ok()) << forced.error().message;
  EXPECT_EQ(forced->kind, DriftModelKind::kHybrid);
}

// Eq. H-1 in closed form: gains g = incumbent - challenger; the kernel wins iff mean(g) > SD(g)
// (the stricter threshold; term_admission_test.cc checks Eq. A-4's mean(g) > SE(g)).
TEST(DriftModelHybrid, PairedFoldGainClosedForm) {
  using drift_internal::KernelWins;
  const std::vector<double> incumbent = {3.0, 3.0, 3.0, 3.0};
  // Steady gain 0.1 on every block: SD 0, wins.
  auto g = PairedTermGain(incumbent, std::vector<double>{2.9, 2.9, 2.9, 2.9});
  EXPECT_NEAR(g.gain, 0.1, 1e-15);
  EXPECT_NEAR(g.Sd(), 0.0, 1e-15);
  EXPECT_EQ(g.pairs, 4u);
  EXPECT_TRUE(KernelWins(g));
  // Gains {1, -0.5, 1, -0.5}: mean 0.25, SD sqrt(4 * 0.75^2 / 3) = 0.866: loses.
  g = PairedTermGain(incumbent, std::vector<double>{2.0, 3.5, 2.0, 3.5});
  EXPECT_NEAR(g.gain, 0.25, 1e-15);
  EXPECT_NEAR(g.Sd(), std::sqrt(4 * 0.5625 / 3.0), 1e-15);
  EXPECT_FALSE(KernelWins(g));
  // Gains {0.3, 0.1, 0.2, 0.2}: mean 0.2, SD sqrt(0.02 / 3) = 0.0816: wins.
  g = PairedTermGain(incumbent, std::vector<double>{2.7, 2.9, 2.8, 2.8});
  EXPECT_NEAR(g.Sd(), std::sqrt(0.02 / 3.0), 1e-15);
  EXPECT_TRUE(KernelWins(g));
  // One block: no spread to judge by, never wins.
  EXPECT_FALSE(KernelWins(PairedTermGain(std::vector<double>{3.0}, std::vector<double>{1.0})));
}

// auto on a calibration run that only cools (and heats once, briefly): the memory and lag
// states, the pure kernel models and the hybrid are not identifiable (validated on one direction
// only), so they are listed but not fitted; the chosen
// model says why; the choice is the same for the same data (deterministic).
TEST(DriftModelAuto, ExplainsItsChoiceAndSkipsWhatTheRunCannotIdentify) {
  const double fs_hz = 0.5;
  std::vector<double> temp(static_cast<std::size_t>(6 * 3600 * fs_hz));
  for (std::size_t i = 0; i < temp.size(); ++i) {
    const double h = static_cast<double>(i) / fs_hz / 3600.0;
    temp[i] = h < 0.5 ? 25.0 + 60.0 * h : std::max(-30.0, 55.0 - 20.0 * (h - 0.5));  // warm-up, then cool
  }
  std::vector<double> y(temp.size());
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = 1e-3 * temp[i] + 2e-5 * temp[i] * temp[i];
  DriftFitOptions o;  // model = auto
  o.search.cuckoo.num_nests = 5;
  o.auto_select.search_generations = 1;
  auto a = FitDriftModel({temp, fs_hz}, y, o);
  ASSERT_TRUE(a.ok()) << a.error().message;
  EXPECT_NE(a->kind, DriftModelKind::kAuto);
  EXPECT_EQ(a->summary.candidates.size(), 8u);  // + poly(temp,dtemp,memory)
  EXPECT_NE(a->summary.selection_reason.find("auto chose"), std::string::npos);
  EXPECT_NE(a->summary.identifiability.find("NOT identifiable"), std::string::npos) << a->summary.identifiability;
  for (const DriftCandidateScore& c : a->summary.candidates)
    if (c.kind == DriftModelKind::kCsSvr || c.kind == DriftModelKind::kHybrid ||
        c.inputs == DriftInputSet::kTempAndMemory || c.inputs == DriftInputSet::kTempAndLag ||
        c.inputs == DriftInputSet::kTempRateAndMemory) {
      EXPECT_FALSE(std::isfinite(c.cv_rmse)) << c.name;
      EXPECT_FALSE(c.note.empty()) << c.name;
    }
  // Exactly quadratic drift: the chosen model reproduces it closely (the structured part holds it).
  EXPECT_LT(Rmse(*a->Predict({temp, fs_hz}), y), 1e-4);
  auto b = FitDriftModel({temp, fs_hz}, y, o);
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(DriftModelToJson(*a), DriftModelToJson(*b));
}

}  // namespace
}  // namespace gyrocomp
