// --model auto: candidates scored on one cross-validation plan (thermal segments), the lag
// state's tau by a 1-D search, and what a calibration run can identify.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "drift_auto_internal.h"
#include "gyrocomp/core/format.h"

namespace gyrocomp::drift_internal {
namespace {

// A direction (heating or cooling) identifies a memory state, and a pure kernel model in
// (T, state), when it covers this share of the fitted temperature range. The paper's profile
// heats once, 25 -> 60 C of -40..60 C (35%): not enough.
constexpr double kMemoryCoverage = 0.5;

// Standard error of the mean of the structured candidate's fold RMSEs (0 when unavailable).
double FoldStandardError(const DriftInputs& inputs, std::span<const double> target, const Candidate& c,
                         const CvPlan& plan, const DriftFitOptions& o) {
  const std::vector<double> folds = FoldRmse(inputs, target, c, o, plan);
  if (folds.size() < 2) return 0.0;
  double mean = 0.0, ss = 0.0;
  for (double v : folds) mean += v / static_cast<double>(folds.size());
  for (double v : folds) ss += (v - mean) * (v - mean);
  return std::sqrt(ss / static_cast<double>(folds.size() - 1)) / std::sqrt(static_cast<double>(folds.size()));
}

// The structured model, term by term, in the nested order poly(T) -> +dT/dt -> +memory / +lag:
// dT/dt enters when Eq. I-1 identifies its gain; a memory or lag enters only when its paired
// leave-one-segment-out CV gain over the simpler model exceeds the SE of those paired gains
// (Eq. A-4, term_admission.h; the lag's tau choice nested in the pairs, Eq. A-5); otherwise the
// simpler model stands. Of +memory and +lag, the admitted one with the larger gain enters. Lowest CV alone chose
// poly(T, dT/dt, memory) on a 1 % CV gain and was six times worse than poly(T, dT/dt) on held-out
// runs of a simulator written apart from this code (docs/explanation/drift-models.md).
std::size_t ChooseStructured(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o,
                             const CvPlan& plan, std::vector<Candidate>* all, std::vector<TermAdmission>* tests) {
  std::vector<Candidate>& c = *all;  // order: temp, temp+dtemp, temp+dtemp+memory, temp+lag, temp+memory[, lagged curve]
  if (!c[0].model) return c[1].model ? 1 : 0;  // poly(T) failed: nothing to test against
  const CvPlan pairs = SegmentPairPlan(plan);
  std::size_t best = 0;
  std::vector<double> incumbent = FoldRmse(inputs, target, c[0], o, pairs);
  std::vector<double> folds = FoldRmse(inputs, target, c[1], o, pairs);
  tests->push_back(TestTerm("dT/dt", c[0], incumbent, c[1], folds));
  // dT/dt enters when Eq. I-1 identifies its gain (the candidate was fitted); its paired gain is
  // reported, not decisive. On the paper's staircase (23 segments, mostly holds where dT/dt is 0)
  // Eq. A-4 rejected a gain Eq. I-1 identified (0.30 +- 0.48 mdps), and poly(T) was then 1.3-2.3x
  // poly(T, dT/dt)'s error on the next heating run (bench/drift_admission.py, structure A).
  if (c[1].model) tests->back().admitted = true, best = 1, incumbent = folds;
  const std::size_t base = best;
  double best_gain = 0.0;
  for (std::size_t i : {base == 1 ? std::size_t{2} : std::size_t{4}, std::size_t{3}}) {
    // The lag's tau was searched on these segments: its choice is nested in the pairs (Eq. A-5).
    folds = i == 3 ? NestedLagFoldRmse(inputs, target, c[i], o, pairs) : FoldRmse(inputs, target, c[i], o, pairs);
    tests->push_back(TestTerm(i == 3 ? "lag" : "memory", c[base], incumbent, c[i], folds));
    if (tests->back().admitted && tests->back().gain.gain > best_gain) best = i, best_gain = tests->back().gain.gain;
  }
  // The lagged curve (c[5]) against the model chosen so far, paired on segment pieces: leaving out
  // a whole ramp leaves one direction at its temperatures, where a gain in T times a ramp's
  // near-constant rate is a polynomial in T, the curve's own form; a piece has the other direction
  // at its temperatures in the training folds (DriftAutoOptions::lagged_curve_pieces).
  if (c.size() > 5) {
    const CvPlan pieces = SegmentPairPlan(plan, o.auto_select.lagged_curve_pieces);
    incumbent = FoldRmse(inputs, target, c[best], o, pieces);
    folds = FoldRmse(inputs, target, c[5], o, pieces);
    tests->push_back(TestTerm("lagged curve", c[best], incumbent, c[5], folds));
    if (tests->back().admitted) best = 5;  // Eq. A-4
  }
  return best;
}

std::string AdmissionReason(const std::vector<TermAdmission>& tests) {
  std::ostringstream why;
  why << "structured terms enter in the order poly(T) -> +dT/dt (when Eq. I-1 identifies its gain) -> +memory / "
         "+lag (only when the paired leave-one-segment-out CV gain over the simpler model exceeds its standard "
         "error, Eq. A-4); a pure kernel only when its paired gain over the chosen structured model on contiguous "
         "blocks exceeds their SD (Eq. H-1):";
  for (const TermAdmission& t : tests) why << " " << t.BriefReport() << ";";
  std::string s = why.str();
  s.pop_back();
  return s;
}

std::string SelectionReason(const std::vector<Candidate>& all, std::size_t best, const CvPlan& plan) {
  std::ostringstream s;
  s << "auto chose " << all[best].score.name << ": CV RMSE " << FormatNumber(all[best].score.cv_rmse, 4) << " ("
    << DriftCvSchemeName(plan.scheme) << ", " << plan.folds << " folds";
  if (plan.scheme == DriftCvScheme::kThermalSegments) s << " leaving out whole segments of " << plan.segments;
  s << "); others:";
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (i == best) continue;
    s << " " << all[i].score.name << " ";
    if (std::isfinite(all[i].score.cv_rmse)) s << FormatNumber(all[i].score.cv_rmse, 4);
    if (!all[i].score.note.empty()) s << " (" << all[i].score.note << ")";
    s << (i + 1 < all.size() ? ";" : "");
  }
  return s.str();
}

Support AssessSupport(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o,
                      const CvPlan& plan, std::size_t points, double train_period_s, std::vector<ExcludedTerm>* excluded) {
  Support s;
  const std::size_t max_coef = MaxCoefficients(points);
  s.max_coefficients = max_coef;
  s.degree = std::min<int>(o.polynomial.degree, std::max<int>(1, static_cast<int>(max_coef) - 1));
  s.states = max_coef >= static_cast<std::size_t>(s.degree + 1 + o.polynomial.dtemp_degree);
  s.two_states = max_coef >= static_cast<std::size_t>(s.degree + 2 + o.polynomial.dtemp_degree);
  s.kernels = points >= kMinKernelPoints;
  s.memory = MemoryIdentifiable(inputs, o);
  std::ostringstream d;
  d << points << " training points (" << FormatNumber(train_period_s, 4) << " s each) support at most " << max_coef
    << " coefficients (Eq. I-0: " << kPointsPerCoefficient << " points per coefficient): degree " << s.degree
    << " in T" << (s.degree < o.polynomial.degree ? " (reduced from " + std::to_string(o.polynomial.degree) + ")" : "")
    << (s.states ? "" : ", no thermal state") << (s.kernels ? "" : ", no kernel (needs >= 60 points)");
  s.description = d.str();
  const std::string would = "a longer or denser run: " + std::to_string(kPointsPerCoefficient) +
                            " training points per coefficient (with block means of " +
                            FormatNumber(train_period_s, 4) + " s)";
  if (!s.states) {
    for (const char* term : {"dT/dt gain", "lag tau", "memory"})
      excluded->push_back({term, "Eq. I-0: " + std::to_string(points) + " points support " + std::to_string(max_coef) +
                                     " coefficients, the temperature polynomial uses " + std::to_string(s.degree + 1),
                           would});
  }
  if (!s.kernels)
    excluded->push_back({"kernel", "Eq. I-0: " + std::to_string(points) + " points, a kernel needs >= " +
                                       std::to_string(kMinKernelPoints), would});
  if (s.states) {
    DriftFitOptions r = o;
    r.inputs = DriftInputSet::kTempAndRate;
    r.polynomial.degree = s.degree;
    auto rd = PrepareFitData(inputs, target, r);
    if (rd.ok()) s.rate = TestRateGain(*rd, plan, r.polynomial);
    else s.rate.why = {"dT/dt gain", rd.error().message, ""};
    if (!s.rate.identified) excluded->push_back(s.rate.why);
    if (!s.memory) {
      const std::string cover = "Eq. I-3: heating or cooling covers < 50% of the fitted range";
      excluded->push_back({"lag tau", cover,
                           "a run that heats and cools over most of the range (simulate --profile heat-cool or cycle)"});
      excluded->push_back({"memory", cover,
                           "a run that heats and cools over most of the range (simulate --profile heat-cool or cycle)"});
    }
  }
  if (s.kernels && !s.memory)
    excluded->push_back({"kernel",
                         "Eq. I-3: the run does not cover both directions; a kernel in (T, state) cannot be validated "
                         "on the other",
                         "a run that heats and cools over most of the range"});
  return s;
}

// The CV scores and the span, with any score larger than the span flagged: such a candidate
// extrapolated a left-out segment far outside what the others cover.
std::string FlagCvScale(const std::vector<Candidate>& all, double span) {
  std::ostringstream s;
  for (const Candidate& c : all)
    if (std::isfinite(c.score.cv_rmse) && c.score.cv_rmse > span)
      s << (s.tellp() > 0 ? ", " : "") << c.score.name << " (" << FormatNumber(c.score.cv_rmse, 3) << ")";
  if (s.tellp() == 0) return "";
  return "; CV RMSE larger than the drift span " + FormatNumber(span, 3) + " for " + s.str() +
         ": on some left-out segment that candidate's inputs lie outside the rest of the run (a state value or "
         "temperature no other segment has) and it extrapolated; its score says it must not be used there, not that "
         "the drift is that large";
}

// The kernel candidates (svr, cs-svr, hybrid), fitted or skipped with the reason, after the
// structured ones: eligible only on runs that heat and cool (Eq. I-3) with enough points (Eq. I-0).
void AddKernelCandidates(const DriftInputs& inputs, std::span<const double> target, DriftFitOptions c,
                         const CvPlan& plan, const Support& sup, std::size_t best_poly, std::vector<Candidate>* out) {
  std::vector<Candidate>& all = *out;
  const bool kernels = sup.memory && sup.kernels;
  const std::string why_not = !sup.kernels ? "not fitted: too few points for a kernel (Eq. I-0)"
                                           : "not fitted: the run does not cover both directions, an RBF kernel "
                                             "cannot extrapolate the state";
  // A pure kernel in (T, dT/dt) when the structured model carries both states the run
  // identifies: the kernel has no memory input, so it can only stand the hysteresis in for a
  // function of dT/dt, which another run at other rates does not share. On 24 rate-cycles
  // calibrations (4 structures x 6 seeds) cs-svr won the segment CV on 8 and was worse than
  // poly(T, dT/dt, memory) on all 16 held-out runs of those 8 (docs/explanation/drift-models.md, "The selection
  // rule"). The hybrid (the two-state polynomial plus a kernel that passes Eq. H-1) stays.
  const bool pure_kernels = kernels && all[best_poly].inputs != DriftInputSet::kTempRateAndMemory;
  const std::string why_not_pure =
      kernels ? "not fitted: the structured model carries both identified states (dT/dt and memory); a kernel "
                "in (T, dT/dt) lacks the memory (the hybrid keeps a kernel on the two-state model)"
              : why_not;
  c.inputs = DriftInputSet::kTempAndRate;
  for (DriftModelKind k : {DriftModelKind::kSvr, DriftModelKind::kCsSvr})
    all.push_back(pure_kernels ? FitCandidate(inputs, target, k, c, plan) : Skipped(k, c.inputs, why_not_pure));
  // The hybrid on the best structured state (and its tau), on runs that heat and cool only: its
  // kernel in (T, state) is validated on the direction(s) the run covers, and on a cooling
  // calibration it learnt what the cooling blocks share (flicker, a hysteresis branch) and
  // applied it to the next heating run: B6 passed Eq. H-1 and was 1.88x poly's heating error.
  c = OptionsOf(all[best_poly], c);
  all.push_back(kernels ? FitCandidate(inputs, target, DriftModelKind::kHybrid, c, plan)
                        : Skipped(DriftModelKind::kHybrid, c.inputs,
                                  !sup.kernels ? why_not
                                               : "not fitted: the run does not cover both directions, its kernel "
                                                 "cannot be validated on the other"));
}

Result<DriftModel> FitAuto(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o,
                           const CvPlan& plan, std::size_t points, double train_period_s, const std::string& plan_note) {
  std::vector<Candidate> all;
  std::vector<ExcludedTerm> excluded;
  const Support sup = AssessSupport(inputs, target, o, plan, points, train_period_s, &excluded);
  DriftFitOptions c = o;
  c.cv_scheme = plan.scheme;
  c.search.cuckoo.max_generations = o.auto_select.search_generations;
  c.polynomial.degree = sup.degree;
  // A gain that varies with T is not an auto candidate: Eq. A-4 rejected it on 23 of 24 two-direction
  // runs of bench/sim2 (docs/explanation/accuracy.md "A gain that varies with temperature").
  c.polynomial.gain_temp_degree = 0;
  const bool memory = sup.memory;
  // Structured candidates: the polynomial with each thermal state the run identifies.
  // Order as ChooseStructured reads it: temp, temp+dtemp, then the two-state model (the memory
  // term on poly(T, dT/dt)), then the lag and the memory alone (on poly(T)).
  for (DriftInputSet in : {DriftInputSet::kTemp, DriftInputSet::kTempAndRate, DriftInputSet::kTempRateAndMemory,
                           DriftInputSet::kTempAndLag, DriftInputSet::kTempAndMemory}) {
    c.inputs = in;
    // poly(T, dT/dt, memory): a unit with a die gain and a hysteresis together needs
    // both states; with one, the gain absorbs the hysteresis on a two-rate run. Fitted only when
    // Eq. I-1 keeps the gain AND Eq. I-3 allows a memory, and one more coefficient fits Eq. I-0.
    if (in == DriftInputSet::kTempRateAndMemory) {
      const char* why = !sup.states || !sup.two_states ? "left out: too few points for two states (Eq. I-0)"
                        : !sup.rate.identified ? "left out: the run does not identify the dT/dt gain (Eq. I-1)"
                        : !memory ? "skipped: the run does not both heat and cool over enough of its range (Eq. I-3)"
                                  : nullptr;
      all.push_back(why ? Skipped(DriftModelKind::kPolynomial, in, why)
                        : FitCandidate(inputs, target, DriftModelKind::kPolynomial, c, plan));
      continue;
    }
    if (in != DriftInputSet::kTemp && !sup.states) {
      all.push_back(Skipped(DriftModelKind::kPolynomial, in, "left out: too few points (Eq. I-0)"));
      continue;
    }
    if (in == DriftInputSet::kTempAndRate && !sup.rate.identified) {
      all.push_back(Skipped(DriftModelKind::kPolynomial, in, "left out: the run does not identify the dT/dt gain (Eq. I-1)"));
      continue;
    }
    // The lag and memory states carry history: on a ramp the lag excess is ~ -tau dT/dt and
    // settles only after ~tau, so a long tau is a direction memory, identified only by a run that
    // both heats and cools. On paper-profile runs (one short heating leg) auto chose lags of
    // 638-5314 s that fitted the cooling blocks and were 1.6-5.1x worse than poly(T, dT/dt) on
    // the next heating run (docs/explanation/drift-models.md "Thermal states").
    if ((in == DriftInputSet::kTempAndMemory || in == DriftInputSet::kTempAndLag) && !memory) {
      all.push_back(Skipped(DriftModelKind::kPolynomial, in,
                            "skipped: the run does not both heat and cool over enough of its range (Eq. I-3)"));
      continue;
    }
    if (in == DriftInputSet::kTempAndLag) {
      all.push_back(FitLagCandidate(inputs, target, c, plan, sup, &excluded));
      continue;
    }
    all.push_back(FitCandidate(inputs, target, DriftModelKind::kPolynomial, c, plan));
  }
  // The lagged curve poly(T) + g(T) (T - T_lag): a state with a history, so on runs that heat
  // and cool only (Eq. I-3, as the lag); Eq. I-0 for its 2 + gain degree coefficients beyond poly(T).
  if (const int gd = o.auto_select.lagged_curve_gain_degree; gd > 0) {
    const std::string name = "poly(temp,lag,gain(temp))";
    if (!memory)
      all.push_back(Skipped(DriftModelKind::kPolynomial, DriftInputSet::kTempAndLag,
                            "skipped: the run does not both heat and cool over enough of its range (Eq. I-3)", name));
    else if (!sup.states || sup.max_coefficients < static_cast<std::size_t>(sup.degree + 2 + gd))
      all.push_back(Skipped(DriftModelKind::kPolynomial, DriftInputSet::kTempAndLag,
                            "left out: too few points for a gain in T (Eq. I-0)", name));
    else
      all.push_back(FitLaggedCurveCandidate(inputs, target, c, plan));
  }
  std::vector<TermAdmission> tests;
  const std::size_t best_poly = ChooseStructured(inputs, target, c, plan, &all, &tests);
  if (o.auto_select.try_svr) AddKernelCandidates(inputs, target, c, plan, sup, best_poly, &all);
  // A kernel candidate must beat the best structured one by one standard error of the latter's
  // fold scores: the CV error is dominated by the flicker bias no model can predict, and a
  // searched model's CV score is optimistic (its parameters were chosen on it), so a small CV
  // gain does not buy a gain on the next run (docs/explanation/drift-models.md).
  const double se = FoldStandardError(inputs, target, all[best_poly], plan, c);
  std::size_t best = best_poly;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (all[i].kind == DriftModelKind::kPolynomial || !all[i].model) continue;
    // A pure kernel (svr, cs-svr) also passes Eq. H-1 against the chosen structured model, the
    // test the hybrid's kernel passes: paired on contiguous blocks, a split its search did not
    // see. The unpaired rule alone let cs-svr in on heat-cool runs of structures A and B
    // (2.5-3.3x poly(T, dT/dt)'s error on the next cooling staircase, bench/drift_admission.py).
    if (all[i].kind != DriftModelKind::kHybrid) {
      tests.push_back(TestKernel(inputs, target, all[best_poly], all[i], c));
      if (!tests.back().admitted) continue;
    }
    if (all[i].score.cv_rmse < all[best_poly].score.cv_rmse - se && all[i].score.cv_rmse < all[best].score.cv_rmse)
      best = i;
  }
  if (!all[best].model) return InvalidInput("--model auto: no candidate could be fitted: " + all[best].score.note);
  const std::string state_reason = AdmissionReason(tests);
  DriftModel model = std::move(*all[best].model);
  for (const Candidate& k : all) model.summary.candidates.push_back(k.score);
  // A hybrid whose kernel Eq. H-1 dropped: the kernel is an excluded term too.
  if (all.back().kind == DriftModelKind::kHybrid && all.back().model &&
      !all.back().model->summary.kernel_decision.empty() && !all.back().model->kernel)
    excluded.push_back({"kernel", all.back().model->summary.kernel_decision,
                        "a longer run whose blocks share the residual structure (Eq. H-1)"});
  if (!sup.rate.identified && std::isfinite(sup.rate.gain) && std::isfinite(sup.rate.gain_se) &&
      model.inputs != DriftInputSet::kTempAndRate && model.inputs != DriftInputSet::kTempRateAndMemory) {
    model.summary.unidentified_rate_gain = sup.rate.gain;
    model.summary.unidentified_rate_gain_se = sup.rate.gain_se;
    model.summary.calibration_rate_vs_temp = sup.rate.rate_vs_temp;
  }
  model.summary.excluded_terms = std::move(excluded);
  model.summary.term_admissions = std::move(tests);
  model.summary.data_support = sup.description + (plan_note.empty() ? "" : "; " + plan_note);
  model.summary.selection_reason = SelectionReason(all, best, plan) + "; " + state_reason +
                                   "; a kernel model must beat the chosen structured one by one standard error of "
                                   "its fold scores (" + FormatNumber(se, 4) + ")" +
                                   FlagCvScale(all, model.summary.drift_span);
  return model;
}

}  // namespace

CvPlan ModelCvPlan(const FitData& base, const DriftFitOptions& o, std::string* note) {
  CvPlan plan = MakeCvPlan(base, o, o.model);
  if (o.model != DriftModelKind::kAuto) return plan;
  // Eq. I-0: every fold must leave enough points for the largest candidate the points support.
  const std::size_t points = base.yd.size();
  const std::size_t coefficients = std::max<std::size_t>(
      2, std::min<std::size_t>(MaxCoefficients(points),
                               static_cast<std::size_t>(o.polynomial.degree + 1 + o.polynomial.dtemp_degree)));
  return EnsureTrainablePlan(plan, base.xd[0], coefficients, o.cv_folds, note);
}

Result<DriftModel> FitSelected(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o) {
  // One plan for every candidate: it depends on the temperature only.
  auto base = PrepareFitData(inputs, target, o);
  if (!base.ok()) return base.error();
  std::string note;
  CvPlan plan = ModelCvPlan(*base, o, &note);
  if (o.model == DriftModelKind::kAuto) return FitAuto(inputs, target, o, plan, base->yd.size(), base->train_period_s, note);
  // A given model with the lag state: tau first, then the model.
  DriftFitOptions c = o;
  c.state.lag_tau_s = SearchLagTau(inputs, target, o, plan);
  auto d = PrepareFitData(inputs, target, c);
  if (!d.ok()) return d.error();
  return FitPrepared(*d, inputs, o.model, c, plan);
}

namespace {

// Temperature span covered while heating (+1) or cooling (-1), and the share of samples.
struct Coverage {
  double lo = kInf, hi = -kInf;
  std::size_t count = 0;
  double span() const { return count ? hi - lo : 0.0; }
};

void Cover(const DriftInputs& inputs, const DriftFitOptions& o, Coverage* heat, Coverage* cool, double* range) {
  auto rate = TemperatureRate(inputs.temp_c, inputs.fs_hz, o.rate);
  if (!rate.ok()) return;
  const auto [a, b] = std::minmax_element(inputs.temp_c.begin(), inputs.temp_c.end());
  *range = *b - *a;
  for (std::size_t i = 0; i < rate->size(); ++i) {
    Coverage* c = (*rate)[i] > kSegmentRateThreshold ? heat : (*rate)[i] < -kSegmentRateThreshold ? cool : nullptr;
    if (!c) continue;
    c->lo = std::min(c->lo, inputs.temp_c[i]);
    c->hi = std::max(c->hi, inputs.temp_c[i]);
    ++c->count;
  }
}

}  // namespace

bool MemoryIdentifiable(const DriftInputs& inputs, const DriftFitOptions& o) {
  Coverage heat, cool;
  double range = 0.0;
  Cover(inputs, o, &heat, &cool, &range);
  return range > 0.0 && heat.span() >= kMemoryCoverage * range && cool.span() >= kMemoryCoverage * range;
}

int UncoveredDirection(const DriftInputs& inputs, const DriftFitOptions& o) {
  Coverage heat, cool;
  double range = 0.0;
  Cover(inputs, o, &heat, &cool, &range);
  if (!(range > 0.0)) return 0;
  const bool heat_short = heat.span() < kMemoryCoverage * range, cool_short = cool.span() < kMemoryCoverage * range;
  if (heat_short && cool_short) return heat.span() <= cool.span() ? 1 : -1;
  return heat_short ? 1 : cool_short ? -1 : 0;
}

std::string DescribeIdentifiability(const DriftInputs& inputs, const DriftFitOptions& o) {
  Coverage heat, cool;
  double range = 0.0;
  Cover(inputs, o, &heat, &cool, &range);
  const double n = static_cast<double>(inputs.temp_c.size());
  auto part = [&](const char* what, const Coverage& c) {
    std::ostringstream s;
    if (!c.count) s << what << ": none";
    else s << what << " over " << FormatNumber(c.lo, 4) << ".." << FormatNumber(c.hi, 4) << " C (" << FormatNumber(100.0 * c.count / n, 4) << "% of samples)";
    return s.str();
  };
  std::ostringstream s;
  s << "calibration run: " << part("heating", heat) << ", " << part("cooling", cool) << ". ";
  if (range > 0.0 && heat.span() >= kMemoryCoverage * range && cool.span() >= kMemoryCoverage * range)
    s << "A heating/cooling memory is identifiable (both directions cover >= 50% of the range).";
  else
    s << "A heating/cooling memory is NOT identifiable from this run (a direction covers < 50% of the range); "
         "dT/dt and lag effects are fitted from the direction(s) present and extrapolated to the other.";
  return s.str();
}

}  // namespace gyrocomp::drift_internal

namespace gyrocomp {

std::string TermAdmission::BriefReport(double scale, const std::string& unit) const {
  std::string s = "+" + term + " (" + candidate + " over " + simpler + "): ";
  if (!note.empty()) return s + note;
  if (term == "kernel")  // Eq. H-1: paired on contiguous blocks, the stricter gain > SD
    return s + gain.BriefReport(scale, unit, "blocks") + ", block SD " + FormatNumber(gain.Sd() * scale, 3) +
           (admitted ? ", admitted (gain > SD, Eq. H-1)" : ", rejected (gain <= SD, Eq. H-1)");
  const std::string g = gain.BriefReport(scale, unit, term == "lagged curve" ? "segment pieces" : "segments");
  if (admitted && !gain.Admitted()) return s + g + ", admitted by Eq. I-1 (its gain is identified; this paired gain is shown, not decisive)";
  return s + g + (admitted ? ", admitted" : ", rejected (gain <= SE)");
}

}  // namespace gyrocomp
