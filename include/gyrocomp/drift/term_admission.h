// Whether a term earns its place in a model: the paired cross-validation gain of the richer
// model over the simpler one, and its standard error.
//
// Both models are scored on the same cross-validation plan (the same held-out folds, e.g. whole
// thermal segments). For each fold k, d_k = RMSE_k(simpler) - RMSE_k(richer) is the richer
// model's gain on that fold (positive: the added term helps). Then
//   gain = mean_k d_k                                   (Eq. A-1)
//   sd   = sqrt(sum_k (d_k - gain)^2 / (K - 1))          (Eq. A-2, the fold-to-fold spread)
//   se   = sd / sqrt(K)                                  (Eq. A-3, the SE of the mean gain)
// and the term is admitted iff gain > se and K >= 2 (Eq. A-4): its gain beats its own
// uncertainty, else the simpler model stands. Pairing removes what both models share on a fold
// (the flicker wander no model predicts), so the test reads only the difference the term makes.
//
// --model auto admits its memory and lag terms by Eq. A-4 (and reports dT/dt's paired gain, which
// Eq. I-1 decides); the hybrid's kernel test asks the stricter gain > Sd() (Eq. H-1). Units: those
// of the fold RMSEs given (deg/s for a gyro).
//
// A richer model with a setting chosen on the same folds (a lag's tau, the best of several lags)
// is scored on them with the choice nested in the pairs (Eq. A-5): fold k gets the RMSE of the
// setting with the lowest mean RMSE over the other folds, so the chosen setting is never scored
// on the fold that chose it (the best of several, read on its own scores, looks better than it
// will on the next run).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace gyrocomp {

// A candidate term's paired CV gain over the simpler model (Eqs. A-1..A-3).
struct TermGain {
  double gain = 0.0;      // Eq. A-1: mean paired fold gain, simpler - richer, units of the RMSEs
  double se = 0.0;        // Eq. A-3: its standard error; +inf with fewer than 2 pairs
  std::size_t pairs = 0;  // folds paired (K)
  // Eq. A-2: the fold-to-fold SD of the paired gains (se * sqrt(pairs)); +inf with < 2 pairs.
  double Sd() const;
  // Eq. A-4: gain > se with at least 2 pairs.
  bool Admitted() const;
  // "gain 0.12 +- 0.05 mdps (7 segments)": gain and se scaled by `scale` (e.g. 1000 for deg/s
  // -> mdps) and labelled `unit`; `what` names the pairs ("segments", "blocks").
  std::string BriefReport(double scale = 1.0, const std::string& unit = "", const std::string& what = "folds") const;
};

// Eqs. A-1..A-3 over the first min(size) folds of the two models' per-fold RMSEs (the same
// plan, fold k in both). Non-finite pairs are skipped.
TermGain PairedTermGain(std::span<const double> simpler_fold_rmse, std::span<const double> richer_fold_rmse);

// The setting with the lowest mean fold RMSE, fold `except` left out (except >= K: none left
// out): scores[c][k] is setting c's RMSE on fold k; non-finite RMSEs are left out of a mean, a
// setting with none finite scores +inf, a tie goes to the lower c, a row whose size differs from
// scores[0]'s is never chosen. 0 when `scores` is empty.
std::size_t LowestMeanSetting(const std::vector<std::vector<double>>& scores, std::size_t except);

// Eq. A-5: the nested fold RMSEs, fold k from the setting LowestMeanSetting(scores, k); the size
// of scores[0] (empty when `scores` is).
std::vector<double> NestedChoiceRmse(const std::vector<std::vector<double>>& scores);

}  // namespace gyrocomp
