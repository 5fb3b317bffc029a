// Internals of --model auto shared by drift_auto.cc (the selection) and drift_auto_terms.cc (the
// candidates with a searched lag and the paired tests). Not installed; not part of the public API.
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "drift_model_internal.h"

namespace gyrocomp::drift_internal {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// One auto candidate: the model when it was fitted, its score (or why not) either way.
struct Candidate {
  DriftModelKind kind;
  DriftInputSet inputs;
  std::optional<DriftModel> model;
  DriftCandidateScore score;
};

// What the run supports before anything is fitted (Eqs. I-0, I-1, I-3): the degree, whether a
// state or a kernel may enter, the dT/dt test. Excluded terms go to *excluded.
struct Support {
  int degree = 3;
  bool states = true;         // Eq. I-0: a state coefficient fits the points
  bool kernels = true;        // Eq. I-0: enough points for a kernel
  bool memory = false;        // Eq. I-3
  bool two_states = false;    // Eq. I-0: one more coefficient than a one-state candidate
  std::size_t max_coefficients = 0;  // Eq. I-0: coefficients the training points support
  TermTest rate;              // Eq. I-1
  std::string description;    // data_support
};

// "poly(temp,lag,gain(temp) tau=120 s)": the candidate's kind, inputs, gain degree and tau.
std::string CandidateName(DriftModelKind kind, DriftInputSet inputs, const DriftFitOptions& o);
// The options a structured candidate was fitted with: its inputs, state and gain degree.
DriftFitOptions OptionsOf(const Candidate& c, DriftFitOptions o);
// Fits one candidate with o.inputs / o.state set; records its score or why it failed.
Candidate FitCandidate(const DriftInputs& inputs, std::span<const double> target, DriftModelKind kind,
                       const DriftFitOptions& o, const CvPlan& plan);
// A candidate left out before it was fitted: scored +inf with the note (named `name` when given).
Candidate Skipped(DriftModelKind kind, DriftInputSet in, const std::string& note, const std::string& name = "");

// Poly CV score of the lag state with time constant tau_s on `plan` (o.polynomial as given,
// its gain degree included).
double LagScore(const DriftInputs& inputs, std::span<const double> target, DriftFitOptions o, double tau_s,
                const CvPlan& plan);
// Golden-section search of log(tau) in [lag_tau_min_s, lag_tau_max_s] on LagScore.
double SearchLagTau(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o,
                    const CvPlan& plan);
// The lag candidate: tau by the 1-D search, then Eq. I-2 on the CV profile around it.
Candidate FitLagCandidate(const DriftInputs& inputs, std::span<const double> target, DriftFitOptions c,
                          const CvPlan& plan, const Support& s, std::vector<ExcludedTerm>* excluded);
// The lagged-curve candidate poly(T) + g(T) (T - T_lag), g of degree
// auto_select.lagged_curve_gain_degree in T, its tau searched with that gain.
Candidate FitLaggedCurveCandidate(const DriftInputs& inputs, std::span<const double> target, DriftFitOptions c,
                                  const CvPlan& plan);

// The plan Eq. A-4 pairs on: one fold per contiguous run of `plan` (a thermal segment, or a block
// when the plan fell back to blocks), each cut into `pieces` contiguous pieces of one fold each.
CvPlan SegmentPairPlan(const CvPlan& plan, int pieces = 1);
// Per-fold RMSEs of a structured candidate's polynomial (OLS, refitted per fold) on `plan`.
std::vector<double> FoldRmse(const DriftInputs& inputs, std::span<const double> target, const Candidate& c,
                             const DriftFitOptions& o, const CvPlan& plan);
// The lag candidate's fold RMSEs on `pairs` with its tau choice nested in them (Eq. A-5).
std::vector<double> NestedLagFoldRmse(const DriftInputs& inputs, std::span<const double> target, const Candidate& lag,
                                      const DriftFitOptions& o, const CvPlan& pairs);
// Eq. A-4 for one term: candidate `richer` against the incumbent's fold RMSEs `simpler_folds`.
TermAdmission TestTerm(const char* term, const Candidate& simpler, const std::vector<double>& simpler_folds,
                       const Candidate& richer, const std::vector<double>& richer_folds);
// Eq. H-1 for a pure kernel candidate against the structured model `incumbent`.
TermAdmission TestKernel(const DriftInputs& inputs, std::span<const double> target, const Candidate& incumbent,
                         const Candidate& kernel, const DriftFitOptions& o);

}  // namespace gyrocomp::drift_internal
