// Paired fold gain of a richer model over a simpler one (include/gyrocomp/drift/term_admission.h).
#include "gyrocomp/drift/term_admission.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "gyrocomp/core/format.h"

namespace gyrocomp {

double TermGain::Sd() const {
  return pairs >= 2 ? se * std::sqrt(static_cast<double>(pairs)) : std::numeric_limits<double>::infinity();
}

bool TermGain::Admitted() const { return pairs >= 2 && gain > se; }  // Eq. A-4

std::string TermGain::BriefReport(double scale, const std::string& unit, const std::string& what) const {
  std::ostringstream s;
  s << "gain " << FormatNumber(gain * scale, 3) << " +- " << FormatNumber(se * scale, 3) << (unit.empty() ? "" : " ")
    << unit << " (" << pairs << " " << what << ")";
  return s.str();
}

TermGain PairedTermGain(std::span<const double> simpler_fold_rmse, std::span<const double> richer_fold_rmse) {
  std::vector<double> d;
  const std::size_t n = std::min(simpler_fold_rmse.size(), richer_fold_rmse.size());
  for (std::size_t k = 0; k < n; ++k) {
    const double g = simpler_fold_rmse[k] - richer_fold_rmse[k];
    if (std::isfinite(g)) d.push_back(g);
  }
  TermGain t;
  t.pairs = d.size();
  const double k = static_cast<double>(t.pairs);
  for (double g : d) t.gain += g / k;  // Eq. A-1
  if (t.pairs < 2) {
    t.se = std::numeric_limits<double>::infinity();
    return t;
  }
  double ss = 0.0;
  for (double g : d) ss += (g - t.gain) * (g - t.gain);
  t.se = std::sqrt(ss / (k - 1.0)) / std::sqrt(k);  // Eqs.
  return t;
}

std::size_t LowestMeanSetting(const std::vector<std::vector<double>>& scores, std::size_t except) {
  auto mean = [&](const std::vector<double>& v) {
    double sum = 0.0, count = 0.0;
    for (std::size_t k = 0; k < v.size(); ++k)
      if (k != except && std::isfinite(v[k])) sum += v[k], count += 1.0;
    return count > 0.0 ? sum / count : std::numeric_limits<double>::infinity();
  };
  std::size_t best = 0;
  double lowest = scores.empty() ? 0.0 : mean(scores[0]);
  for (std::size_t c = 1; c < scores.size(); ++c) {
    if (scores[c].size() != scores[0].size()) continue;
    if (const double m = mean(scores[c]); m < lowest) best = c, lowest = m;
  }
  return best;
}

std::vector<double> NestedChoiceRmse(const std::vector<std::vector<double>>& scores) {
  if (scores.empty()) return {};
  std::vector<double> nested(scores[0].size());
  for (std::size_t k = 0; k < nested.size(); ++k) nested[k] = scores[LowestMeanSetting(scores, k)][k];  // Eq. A-5
  return nested;
}

}  // namespace gyrocomp
