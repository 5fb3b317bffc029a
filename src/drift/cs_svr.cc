// Blocked cross-validation and the parameter searches of the SVR family (CS-SVR, grid).
#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include "drift_model_internal.h"

namespace gyrocomp::drift_internal {
namespace {

Columns Rows(const Columns& x, std::size_t a, std::size_t b) {  // rows [a, b)
  Columns out;
  for (const auto& c : x) out.emplace_back(c.begin() + a, c.begin() + b);
  return out;
}

// Fit-and-predict with fixed SVR options.
FitPredict SvrFitPredict(const SvrOptions& o) {
  return [o](const Columns& tx, std::span<const double> ty,
             const Columns& vx) -> Result<std::vector<double>> {
    auto m = FitSvr(tx, ty, o);
    if (!m.ok()) return m.error();
    return m->Predict(vx);
  };
}

// The options one search point stands for: x = (C, sigma[, epsilon]).
SvrOptions PointOptions(const SvrOptions& base, std::span<const double> x) {
  SvrOptions o = base;
  o.C = x[0];
  o.gamma.reset();
  o.sigma = x[1];  // Eq. (20): gamma = 1 / (2 sigma^2)
  if (x.size() > 2) o.epsilon = x[2];
  return o;
}

}  // namespace

Result<double> BlockedCvRmse(const Columns& x, std::span<const double> y, int folds,
                             bool in_range_only, const FitPredict& fit_predict) {
  const std::size_t n = y.size();
  if (folds < 2 || n < 2 * static_cast<std::size_t>(folds))
    return InvalidInput("blocked cross-validation: " + std::to_string(folds) + " folds need at least " +
                        std::to_string(2 * folds) + " training samples, got " + std::to_string(n));
  double ss = 0.0;
  std::size_t scored = 0;
  for (int k = 0; k < folds; ++k) {
    const std::size_t a = n * k / folds;
    const std::size_t b = n * (k + 1) / folds;
    Columns tx;
    for (const auto& c : x) {
      std::vector<double> col(c.begin(), c.begin() + a);
      col.insert(col.end(), c.begin() + b, c.end());
      tx.push_back(std::move(col));
    }
    std::vector<double> ty(y.begin(), y.begin() + a);
    ty.insert(ty.end(), y.begin() + b, y.end());
    auto pred = fit_predict(tx, ty, Rows(x, a, b));
    if (!pred.ok()) return pred.error();
    const auto [lo, hi] = std::minmax_element(tx[0].begin(), tx[0].end());
    for (std::size_t i = a; i < b; ++i) {
      if (in_range_only && (x[0][i] < *lo || x[0][i] > *hi)) continue;
      ss += ((*pred)[i - a] - y[i]) * ((*pred)[i - a] - y[i]);
      ++scored;
    }
  }
  if (scored == 0)
    return InvalidInput("blocked cross-validation: no held-out sample lies inside the temperature range of the "
                        "other blocks (a monotonic sweep?); set cv_in_range_only = false (--cv-all)");
  return std::sqrt(ss / static_cast<double>(scored));
}

long CuckooBudget(const CuckooSearchOptions& o) {
  const long full = static_cast<long>(o.num_nests) * (1 + 2 * static_cast<long>(o.max_generations));
  return o.max_evaluations ? std::min(full, *o.max_evaluations) : full;
}

Result<SvrChoice> SearchSvrCuckoo(const Columns& x, std::span<const double> y,
                                  const DriftFitOptions& options) {
  const SvrSearchOptions& s = options.search;
  std::vector<SearchDimension> dims = {s.C, s.sigma};
  if (s.epsilon) dims.push_back(*s.epsilon);
  // Fitness: blocked CV RMSE (method.md section 4); a failed fit counts as +infinity.
  auto objective = [&](std::span<const double> p) {
    auto r = BlockedCvRmse(x, y, options.cv_folds, options.cv_in_range_only, SvrFitPredict(PointOptions(options.svr, p)));
    return r.ok() ? *r : std::numeric_limits<double>::infinity();
  };
  auto found = CuckooSearch(objective, dims, s.cuckoo);
  if (!found.ok()) return found.error();
  if (!std::isfinite(found->best_value))
    return InternalError("cuckoo search: no parameter set could be fitted (every SVR fit failed)");
  SvrChoice choice;
  choice.options = PointOptions(options.svr, found->best_x);
  choice.cv_rmse = found->best_value;
  choice.evaluations = found->evaluations;
  choice.generations = found->generations;
  choice.history = found->best_value_history;
  return choice;
}

Result<SvrChoice> SearchSvrGrid(const Columns& x, std::span<const double> y,
                                const DriftFitOptions& options) {
  const SvrSearchOptions& s = options.search;
  const long budget = s.grid_budget.value_or(CuckooBudget(s.cuckoo));
  // Square grid over C x sigma, log-spaced (both dimensions are scale parameters).
  const int side = std::max(2, static_cast<int>(std::floor(std::sqrt(static_cast<double>(budget)))));
  auto axis = [side](const SearchDimension& d, int i) {
    const double u = static_cast<double>(i) / (side - 1);
    return d.log_scale ? std::pow(10.0, std::log10(d.lower) + u * (std::log10(d.upper) - std::log10(d.lower)))
                       : d.lower + u * (d.upper - d.lower);
  };
  std::vector<std::vector<double>> points;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) {
      std::vector<double> p = {axis(s.C, i), axis(s.sigma, j)};
      points.push_back(p);
    }
  auto objective = [&](std::span<const double> p) {
    auto r = BlockedCvRmse(x, y, options.cv_folds, options.cv_in_range_only, SvrFitPredict(PointOptions(options.svr, p)));
    return r.ok() ? *r : std::numeric_limits<double>::infinity();
  };
  const int threads = s.cuckoo.num_threads.value_or(static_cast<int>(std::thread::hardware_concurrency()));
  const std::vector<double> v = EvaluateInParallel(objective, points, std::max(1, threads));
  const std::size_t best = std::min_element(v.begin(), v.end()) - v.begin();
  if (!std::isfinite(v[best])) return InternalError("grid search: every SVR fit failed");
  SvrChoice choice;
  choice.options = PointOptions(options.svr, points[best]);
  choice.cv_rmse = v[best];
  choice.evaluations = static_cast<long>(points.size());
  return choice;
}

}  // namespace gyrocomp::drift_internal
