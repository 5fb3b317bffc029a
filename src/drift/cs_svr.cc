// Blocked cross-validation and the parameter searches of the SVR family (CS-SVR, grid).
#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include "drift_model_internal.h"

namespace gyrocomp::drift_internal {
namespace {

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

FitPredict SvrFitPredict(const SvrOptions& o) {
  return [o](const Columns& tx, std::span<const double> ty,
             const Columns& vx) -> Result<std::vector<double>> {
    auto m = FitSvr(tx, ty, o);
    if (!m.ok()) return m.error();
    return m->Predict(vx);
  };
}

CvPlan BlockPlan(std::size_t n, int folds, bool in_range_only) {
  CvPlan plan;
  plan.folds = folds;
  plan.in_range_only = in_range_only;
  plan.fold_of.resize(n);
  for (int k = 0; k < folds; ++k)
    for (std::size_t i = n * k / folds; i < n * (k + 1) / folds; ++i) plan.fold_of[i] = k;
  return plan;
}

CvPlan SegmentPlan(std::span<const double> rate, int folds, double threshold) {
  const std::size_t n = rate.size();
  auto direction = [&](std::size_t i) { return rate[i] > threshold ? 1 : rate[i] < -threshold ? -1 : 0; };
  // Segment starts: where the direction changes; runs shorter than min_run join the previous.
  const std::size_t min_run = std::max<std::size_t>(3, n / 100);
  std::vector<std::size_t> starts = {0};
  for (std::size_t i = 1; i < n; ++i) {
    if (direction(i) == direction(i - 1)) continue;
    std::size_t run = i;
    while (run < n && direction(run) == direction(i)) ++run;
    if (run - i >= min_run && i - starts.back() >= min_run) starts.push_back(i);
  }
  if (starts.size() < 2) return BlockPlan(n, folds, false);
  CvPlan plan;
  plan.scheme = DriftCvScheme::kThermalSegments;
  plan.segments = static_cast<int>(starts.size());
  plan.folds = std::min<int>(folds, plan.segments);
  plan.fold_of.resize(n);
  plan.direction_of.resize(n);
  for (std::size_t j = 0; j < starts.size(); ++j) {
    const std::size_t end = j + 1 < starts.size() ? starts[j + 1] : n;
    for (std::size_t i = starts[j]; i < end; ++i) {
      plan.fold_of[i] = static_cast<int>(j % plan.folds);
      plan.direction_of[i] = direction(starts[j]) + 1;
    }
  }
  return plan;
}

Result<double> CrossValidate(const Columns& x, std::span<const double> y, const CvPlan& plan,
                             const FitPredict& fit_predict, std::vector<double>* fold_rmse) {
  const std::size_t n = y.size();
  if (plan.folds < 2 || n < 2 * static_cast<std::size_t>(plan.folds) || plan.fold_of.size() != n)
    return InvalidInput("cross-validation: " + std::to_string(plan.folds) + " folds need at least " +
                        std::to_string(2 * plan.folds) + " training samples, got " + std::to_string(n));
  const bool balanced = plan.direction_of.size() == n;
  double ss[3] = {0.0, 0.0, 0.0};  // per direction when balanced, else all in [0]
  std::size_t count[3] = {0, 0, 0};
  std::size_t scored = 0;
  for (int k = 0; k < plan.folds; ++k) {
    Columns tx(x.size()), vx(x.size());
    std::vector<double> ty, vy;
    std::vector<int> vd;
    for (std::size_t i = 0; i < n; ++i) {
      const bool held_out = plan.fold_of[i] == k;
      for (std::size_t j = 0; j < x.size(); ++j) (held_out ? vx : tx)[j].push_back(x[j][i]);
      (held_out ? vy : ty).push_back(y[i]);
      if (held_out) vd.push_back(balanced ? plan.direction_of[i] : 0);
    }
    if (ty.empty() || vy.empty()) continue;
    auto pred = fit_predict(tx, ty, vx);
    if (!pred.ok()) return pred.error();
    const auto [lo, hi] = std::minmax_element(tx[0].begin(), tx[0].end());
    double fold_ss = 0.0;
    std::size_t fold_n = 0;
    for (std::size_t i = 0; i < vy.size(); ++i) {
      if (plan.in_range_only && (vx[0][i] < *lo || vx[0][i] > *hi)) continue;
      const double e2 = ((*pred)[i] - vy[i]) * ((*pred)[i] - vy[i]);
      ss[vd[i]] += e2;
      ++count[vd[i]];
      ++scored;
      fold_ss += e2;
      ++fold_n;
    }
    if (fold_rmse && fold_n > 0) fold_rmse->push_back(std::sqrt(fold_ss / static_cast<double>(fold_n)));
  }
  if (scored > 0 && balanced) {
    double mse = 0.0;
    int present = 0;
    for (int d = 0; d < 3; ++d)
      if (count[d] > 0) mse += ss[d] / static_cast<double>(count[d]), ++present;
    return std::sqrt(mse / present);
  }
  if (scored == 0)
    return InvalidInput("blocked cross-validation: no held-out sample lies inside the temperature range of the "
                        "other blocks (a monotonic sweep?); set cv_in_range_only = false (--cv-all)");
  return std::sqrt(ss[0] / static_cast<double>(scored));
}

long CuckooBudget(const CuckooSearchOptions& o) {
  const long full = static_cast<long>(o.num_nests) * (1 + 2 * static_cast<long>(o.max_generations));
  return o.max_evaluations ? std::min(full, *o.max_evaluations) : full;
}

Result<SvrChoice> SearchSvrCuckoo(const Columns& x, std::span<const double> y, const DriftFitOptions& options,
                                  const CvPlan& plan, const MakeFitPredict& make) {
  const SvrSearchOptions& s = options.search;
  std::vector<SearchDimension> dims = {s.C, s.sigma};
  if (s.epsilon) dims.push_back(*s.epsilon);
  // Every fit of the search and the final refit poll the search's token.
  SvrOptions base = options.svr;
  if (s.cuckoo.cancel != nullptr) base.cancel = s.cuckoo.cancel;
  // Fitness: blocked CV RMSE (method.md section 4); a failed fit counts as +infinity.
  auto objective = [&](std::span<const double> p) {
    auto r = CrossValidate(x, y, plan, make(PointOptions(base, p)));
    return r.ok() ? *r : std::numeric_limits<double>::infinity();
  };
  auto found = CuckooSearch(objective, dims, s.cuckoo);
  if (!found.ok()) return found.error();
  if (!std::isfinite(found->best_value))
    return InternalError("cuckoo search: no parameter set could be fitted (every SVR fit failed)");
  SvrChoice choice;
  choice.options = PointOptions(base, found->best_x);
  choice.cv_rmse = found->best_value;
  choice.evaluations = found->evaluations;
  choice.generations = found->generations;
  choice.history = found->best_value_history;
  return choice;
}

Result<SvrChoice> SearchSvrGrid(const Columns& x, std::span<const double> y, const DriftFitOptions& options,
                                const CvPlan& plan, const MakeFitPredict& make) {
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
    auto r = CrossValidate(x, y, plan, make(PointOptions(options.svr, p)));
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
