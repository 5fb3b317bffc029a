// --model auto's candidates with a searched lag state and the paired tests that admit a term
// (Eq. A-4, term_admission.h) or a pure kernel (Eq. H-1).
#include <algorithm>
#include <cmath>
#include <string>

#include "drift_auto_internal.h"
#include "gyrocomp/core/format.h"

namespace gyrocomp::drift_internal {

std::string CandidateName(DriftModelKind kind, DriftInputSet inputs, const DriftFitOptions& o) {
  std::string name = std::string(DriftModelKindName(kind)) + "(" + DriftInputSetName(inputs);
  if (inputs != DriftInputSet::kTemp && o.polynomial.gain_temp_degree > 0 && kind != DriftModelKind::kSvr &&
      kind != DriftModelKind::kCsSvr)
    name += ",gain(temp)";
  if (inputs == DriftInputSet::kTempAndLag) name += " tau=" + FormatNumber(o.state.lag_tau_s, 4) + " s";
  return name + ")";
}

// The options a structured candidate was fitted with: its inputs, state and gain degree.
DriftFitOptions OptionsOf(const Candidate& c, DriftFitOptions o) {
  o.inputs = c.inputs;
  if (c.model) {
    o.state = c.model->state;
    o.polynomial.gain_temp_degree = c.model->summary.gain_temp_degree;
  }
  return o;
}

// Fits one candidate with o.inputs / o.state set; records its score or why it failed.
Candidate FitCandidate(const DriftInputs& inputs, std::span<const double> target, DriftModelKind kind,
                       const DriftFitOptions& o, const CvPlan& plan) {
  ThrowIfCancelled(o.cancel);
  Candidate c{kind, o.inputs, std::nullopt, {CandidateName(kind, o.inputs, o), kind, o.inputs, kInf, ""}};
  auto d = PrepareFitData(inputs, target, o);
  if (!d.ok()) {
    c.score.note = d.error().message;
    return c;
  }
  auto m = FitPrepared(*d, inputs, kind, o, plan);
  if (!m.ok()) {
    c.score.note = m.error().message;
    return c;
  }
  c.score.cv_rmse = m->summary.cv_rmse;
  c.model = std::move(*m);
  return c;
}

// A candidate left out before it was fitted: scored +inf with the note.
Candidate Skipped(DriftModelKind kind, DriftInputSet in, const std::string& note, const std::string& name) {
  return {kind, in, std::nullopt,
          {name.empty() ? std::string(DriftModelKindName(kind)) + "(" + DriftInputSetName(in) + ")" : name, kind, in,
           kInf, note}};
}

// Poly CV score of the lag state with time constant tau_s on `plan`.
double LagScore(const DriftInputs& inputs, std::span<const double> target, DriftFitOptions o, double tau_s,
                const CvPlan& plan) {
  ThrowIfCancelled(o.cancel);
  o.inputs = DriftInputSet::kTempAndLag;
  o.state.lag_tau_s = tau_s;
  auto d = PrepareFitData(inputs, target, o);
  if (!d.ok()) return kInf;
  auto cv = CrossValidate(d->xd, d->yd, plan, [&](const Columns& tx, std::span<const double> ty, const Columns& vx)
                                                  -> Result<std::vector<double>> {
    auto m = FitPolynomial(tx, ty, o.polynomial);
    if (!m.ok()) return m.error();
    return m->Predict(vx);
  });
  return cv.ok() ? *cv : kInf;
}

// Golden-section search of log(tau) in [lag_tau_min_s, lag_tau_max_s] on the polynomial's CV
// score (the structured part decides the physics; the kernel only corrects it).
double SearchLagTau(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o,
                    const CvPlan& plan) {
  const DriftAutoOptions& a = o.auto_select;
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double lo = std::log(a.lag_tau_min_s), hi = std::log(a.lag_tau_max_s);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = LagScore(inputs, target, o, std::exp(x1), plan);
  double f2 = LagScore(inputs, target, o, std::exp(x2), plan);
  for (int k = 2; k < a.lag_tau_evaluations; ++k) {
    if (f1 <= f2) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = LagScore(inputs, target, o, std::exp(x1), plan);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = LagScore(inputs, target, o, std::exp(x2), plan);
    }
  }
  return std::exp(f1 <= f2 ? x1 : x2);
}

// The lag candidate: tau by the 1-D search, then Eq. I-2 on the CV profile around it.
Candidate FitLagCandidate(const DriftInputs& inputs, std::span<const double> target, DriftFitOptions c,
                          const CvPlan& plan, const Support& s, std::vector<ExcludedTerm>* excluded) {
  c.inputs = DriftInputSet::kTempAndLag;
  c.state.lag_tau_s = SearchLagTau(inputs, target, c, plan);
  const double tau = c.state.lag_tau_s;
  const TermTest t = TestLagTau(tau, LagScore(inputs, target, c, tau, plan), LagScore(inputs, target, c, tau / 3.0, plan),
                                LagScore(inputs, target, c, 3.0 * tau, plan), s.rate.identified, s.memory);
  if (!t.identified) {
    excluded->push_back(t.why);
    return Skipped(DriftModelKind::kPolynomial, c.inputs, "left out: the run does not identify tau (" + t.evidence + ")");
  }
  return FitCandidate(inputs, target, DriftModelKind::kPolynomial, c, plan);
}

// The lagged-curve candidate: the drift as a function of a temperature seen through a first-order
// lag, f(T_lag) ~ f(T) + f'(T) (T_lag - T): poly(T) plus the lag state with a gain that is a
// polynomial in T (PolynomialOptions::gain_temp_degree), tau searched with that gain (the constant
// gain's CV profile is flat where the lag acts like a dT/dt term). No Eq. I-2 gate: Eq. A-4 on
// segment pieces decides (ChooseStructured).
Candidate FitLaggedCurveCandidate(const DriftInputs& inputs, std::span<const double> target, DriftFitOptions c,
                                  const CvPlan& plan) {
  c.inputs = DriftInputSet::kTempAndLag;
  c.polynomial.gain_temp_degree = c.auto_select.lagged_curve_gain_degree;
  // tau on contiguous blocks (the Eq. H-1 plan, in range only): on whole left-out ramps the search
  // sees a gain in T confounded with the curve, and on short segment pieces a long tau (a direction
  // memory) carries the neighbouring pieces' residual; both drifted to the longest tau.
  c.state.lag_tau_s = SearchLagTau(inputs, target, c, GainTestPlan(plan.fold_of.size(), c));
  return FitCandidate(inputs, target, DriftModelKind::kPolynomial, c, plan);
}

// The plan Eq. A-4 pairs on: one fold per contiguous run of `plan` (a thermal segment, or a block
// when the plan fell back to blocks), so that each segment is predicted by a model fitted on all
// the others and two models' errors are paired segment by segment. With pieces > 1 each run is
// cut into that many contiguous pieces (fewer when a piece would hold < 2 samples), one fold each:
// a left-out piece of a ramp then has the other direction at its temperatures in the training
// folds. `plan` itself when the folds are too many for CrossValidate (fewer than 2 samples each).
CvPlan SegmentPairPlan(const CvPlan& plan, int pieces) {
  CvPlan p = plan;
  const std::size_t n = plan.fold_of.size();
  int fold = 0;
  for (std::size_t b = 0; b < n;) {
    std::size_t e = b + 1;
    while (e < n && plan.fold_of[e] == plan.fold_of[b]) ++e;
    const std::size_t len = e - b;
    const std::size_t k = std::max<std::size_t>(1, std::min<std::size_t>(static_cast<std::size_t>(pieces), len / 2));
    for (std::size_t j = 0; j < k; ++j, ++fold)
      for (std::size_t i = b + len * j / k; i < b + len * (j + 1) / k; ++i) p.fold_of[i] = fold;
    b = e;
  }
  p.folds = fold;
  p.direction_of.clear();  // per-segment RMSEs: no direction balance within a segment
  if (p.folds < 2 || n < 2 * static_cast<std::size_t>(p.folds)) return plan;
  return p;
}

// Per-fold RMSEs of a polynomial with options `f` (inputs, state, gain degree), refitted by OLS
// per fold of `plan`; empty when it cannot be scored there.
std::vector<double> PolyFoldRmse(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& f,
                                 const CvPlan& plan) {
  std::vector<double> folds;
  auto d = PrepareFitData(inputs, target, f);
  if (!d.ok() || d->yd.size() != plan.fold_of.size()) return folds;
  auto cv = CrossValidate(
      d->xd, d->yd, plan,
      [&](const Columns& tx, std::span<const double> ty, const Columns& vx) -> Result<std::vector<double>> {
        auto m = FitPolynomial(tx, ty, f.polynomial);
        if (!m.ok()) return m.error();
        return m->Predict(vx);
      },
      &folds);
  if (!cv.ok()) folds.clear();
  return folds;
}

// Per-fold RMSEs of a structured candidate's polynomial (OLS, refitted per fold) on `plan`.
std::vector<double> FoldRmse(const DriftInputs& inputs, std::span<const double> target, const Candidate& c,
                             const DriftFitOptions& o, const CvPlan& plan) {
  if (!c.model) return {};
  return PolyFoldRmse(inputs, target, OptionsOf(c, o), plan);
}

// The lag candidate's fold RMSEs with its tau choice nested in the pairs (Eq. A-5): its tau was
// searched on the segments Eq. A-4 then pairs on, so each segment is scored with the tau, of
// the searched one and lag_tau_evaluations log-spaced over [lag_tau_min_s, lag_tau_max_s], that
// has the lowest mean RMSE over the other segments.
std::vector<double> NestedLagFoldRmse(const DriftInputs& inputs, std::span<const double> target, const Candidate& lag,
                                      const DriftFitOptions& o, const CvPlan& pairs) {
  if (!lag.model) return {};
  const DriftFitOptions f = OptionsOf(lag, o);
  std::vector<std::vector<double>> scores{PolyFoldRmse(inputs, target, f, pairs)};
  const DriftAutoOptions& a = o.auto_select;
  const int n = std::max(2, a.lag_tau_evaluations);
  for (int k = 0; k < n; ++k) {
    ThrowIfCancelled(o.cancel);
    DriftFitOptions g = f;
    g.state.lag_tau_s = a.lag_tau_min_s * std::pow(a.lag_tau_max_s / a.lag_tau_min_s, k / static_cast<double>(n - 1));
    scores.push_back(PolyFoldRmse(inputs, target, g, pairs));
  }
  return NestedChoiceRmse(scores);
}

// Eq. A-4 for one term: candidate `richer` against the incumbent's fold RMSEs `simpler_folds`.
TermAdmission TestTerm(const char* term, const Candidate& simpler, const std::vector<double>& simpler_folds,
                       const Candidate& richer, const std::vector<double>& richer_folds) {
  TermAdmission t{term, richer.score.name, simpler.score.name, {}, false, ""};
  if (!richer.model) {
    t.note = richer.score.note.empty() ? "not fitted" : richer.score.note;
    return t;
  }
  if (simpler_folds.empty() || richer_folds.size() != simpler_folds.size()) {
    t.note = "not tested: the segment cross-validation did not score both models";
    return t;
  }
  t.gain = PairedTermGain(simpler_folds, richer_folds);
  t.admitted = t.gain.Admitted();
  return t;
}

// Eq. H-1 for a pure kernel candidate: its searched SVR (C, gamma, epsilon fixed) against the
// structured model `incumbent`, both refitted on every fold of the contiguous-block plan of
// Eq. H-1 (GainTestPlan) and paired block by block; admitted iff mean gain > block-to-block SD.
TermAdmission TestKernel(const DriftInputs& inputs, std::span<const double> target, const Candidate& incumbent,
                         const Candidate& kernel, const DriftFitOptions& o) {
  TermAdmission t{"kernel", kernel.score.name, incumbent.score.name, {}, false, ""};
  if (!incumbent.model || !kernel.model) {
    t.note = "not tested: a model was not fitted";
    return t;
  }
  const DriftFitOptions fs = OptionsOf(incumbent, o);
  DriftFitOptions fk = o;
  fk.inputs = kernel.inputs;
  auto ds = PrepareFitData(inputs, target, fs);
  auto dk = PrepareFitData(inputs, target, fk);
  if (!ds.ok() || !dk.ok() || ds->yd.size() != dk->yd.size()) {
    t.note = "not tested: the two models' training copies differ";
    return t;
  }
  const CvPlan blocks = GainTestPlan(ds->yd.size(), o);
  SvrOptions chosen = o.svr;
  const DriftFitSummary& k = kernel.model->summary;
  if (!k.C || !k.gamma || !k.epsilon) {
    t.note = "not tested: the kernel's parameters are not recorded";
    return t;
  }
  chosen.C = *k.C;
  chosen.gamma = k.gamma;
  chosen.sigma.reset();
  chosen.epsilon = *k.epsilon;
  std::vector<double> structured, kernel_folds;
  auto a = CrossValidate(
      ds->xd, ds->yd, blocks,
      [&](const Columns& tx, std::span<const double> ty, const Columns& vx) -> Result<std::vector<double>> {
        auto m = FitPolynomial(tx, ty, fs.polynomial);
        if (!m.ok()) return m.error();
        return m->Predict(vx);
      },
      &structured);
  auto b = CrossValidate(dk->xd, dk->yd, blocks, SvrFitPredict(chosen), &kernel_folds);
  if (!a.ok() || !b.ok() || structured.size() != kernel_folds.size()) {
    t.note = "not tested: the block cross-validation did not score both models";
    return t;
  }
  t.gain = PairedTermGain(structured, kernel_folds);
  t.admitted = KernelWins(t.gain);
  return t;
}

}  // namespace gyrocomp::drift_internal
