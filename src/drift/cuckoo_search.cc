// Cuckoo search (Yang & Deb 2009) with Levy flights by Mantegna's algorithm; see cuckoo_search.h.
#include "gyrocomp/drift/cuckoo_search.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>
#include <sstream>
#include <thread>

namespace gyrocomp {
namespace {

std::string Num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

double Sanitize(double v) { return std::isfinite(v) ? v : std::numeric_limits<double>::infinity(); }

// Internal (searched) coordinate <-> natural units.
struct Space {
  std::vector<double> lo, hi;
  std::vector<bool> log;
  std::vector<double> ToNatural(const std::vector<double>& z) const {
    std::vector<double> x(z.size());
    for (std::size_t j = 0; j < z.size(); ++j) x[j] = log[j] ? std::pow(10.0, z[j]) : z[j];
    return x;
  }
  void Clip(std::vector<double>& z) const {
    for (std::size_t j = 0; j < z.size(); ++j) z[j] = std::clamp(z[j], lo[j], hi[j]);
  }
};

// Mantegna's sigma_u for exponent beta:
// sigma_u = [Gamma(1+b) sin(pi b / 2) / (Gamma((1+b)/2) b 2^((b-1)/2))]^(1/b).
double MantegnaSigma(double beta) {
  const double num = std::tgamma(1.0 + beta) * std::sin(std::numbers::pi * beta / 2.0);
  const double den = std::tgamma((1.0 + beta) / 2.0) * beta * std::pow(2.0, (beta - 1.0) / 2.0);
  return std::pow(num / den, 1.0 / beta);
}

}  // namespace

bool CuckooSearchOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = "CuckooSearchOptions::" + what;
    return false;
  };
  if (num_nests < 2) return fail("num_nests = " + std::to_string(num_nests) + ": must be >= 2");
  if (!(discovery_probability >= 0.0 && discovery_probability <= 1.0))
    return fail("discovery_probability = " + Num(discovery_probability) + ": must be in [0, 1]");
  if (!(levy_beta > 0.0 && levy_beta <= 2.0))
    return fail("levy_beta = " + Num(levy_beta) + ": must be in (0, 2]");
  if (!(step_scale > 0.0) || !std::isfinite(step_scale))
    return fail("step_scale = " + Num(step_scale) + ": must be > 0");
  if (max_generations < 0)
    return fail("max_generations = " + std::to_string(max_generations) + ": must be >= 0");
  if (max_evaluations && *max_evaluations < num_nests)
    return fail("max_evaluations = " + std::to_string(*max_evaluations) +
                ": must be >= num_nests (" + std::to_string(num_nests) + ")");
  if (num_threads && *num_threads < 1)
    return fail("num_threads = " + std::to_string(*num_threads) + ": must be >= 1");
  return true;
}

const char* CuckooTerminationName(CuckooTermination t) {
  switch (t) {
    case CuckooTermination::kMaxGenerations: return "max generations";
    case CuckooTermination::kMaxEvaluations: return "max evaluations";
    case CuckooTermination::kTargetReached: return "target reached";
  }
  return "?";
}

std::string CuckooSearchSummary::BriefReport() const {
  std::ostringstream s;
  s << "cuckoo search: best " << best_value << " at (";
  for (std::size_t j = 0; j < best_x.size(); ++j) s << (j ? ", " : "") << best_x[j];
  s << "), " << generations << " generations, " << evaluations << " evaluations, " << num_threads
    << " threads, stopped: " << CuckooTerminationName(termination) << ", " << time_s << " s";
  return s.str();
}

std::vector<double> EvaluateInParallel(const SearchObjective& objective,
                                       const std::vector<std::vector<double>>& points,
                                       int num_threads) {
  std::vector<double> values(points.size(), std::numeric_limits<double>::infinity());
  const int workers = std::max(1, std::min<int>(num_threads, static_cast<int>(points.size())));
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t i = next++; i < points.size(); i = next++)
      values[i] = Sanitize(objective(points[i]));
  };
  if (workers == 1) {
    work();
    return values;
  }
  std::vector<std::thread> threads;
  for (int t = 1; t < workers; ++t) threads.emplace_back(work);
  work();
  for (auto& th : threads) th.join();
  return values;
}

Result<CuckooSearchSummary> CuckooSearch(const SearchObjective& objective,
                                         std::span<const SearchDimension> dimensions,
                                         const CuckooSearchOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (dimensions.empty()) return InvalidArgument("CuckooSearch: no dimensions to search");
  Space space;
  for (const SearchDimension& d : dimensions) {
    const std::string name = "SearchDimension '" + d.name + "'";
    if (!std::isfinite(d.lower) || !std::isfinite(d.upper) || !(d.lower < d.upper))
      return InvalidArgument(name + ": bounds [" + Num(d.lower) + ", " + Num(d.upper) +
                             "]: need finite lower < upper");
    if (d.log_scale && !(d.lower > 0.0))
      return InvalidArgument(name + ": log_scale needs lower > 0, got " + Num(d.lower));
    space.lo.push_back(d.log_scale ? std::log10(d.lower) : d.lower);
    space.hi.push_back(d.log_scale ? std::log10(d.upper) : d.upper);
    space.log.push_back(d.log_scale);
  }
  const std::size_t dim = dimensions.size();
  const int n = options.num_nests;
  int threads = options.num_threads.value_or(static_cast<int>(std::thread::hardware_concurrency()));
  threads = std::max(1, threads);
  const long max_evals = options.max_evaluations.value_or(std::numeric_limits<long>::max());

  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);

  CuckooSearchSummary summary;
  summary.num_threads = threads;

  // Evaluates up to the remaining budget; candidates beyond it are not evaluated (value +inf).
  auto evaluate = [&](const std::vector<std::vector<double>>& nests) {
    const long left = max_evals - summary.evaluations;
    const std::size_t count = static_cast<std::size_t>(std::min<long>(left, static_cast<long>(nests.size())));
    std::vector<std::vector<double>> natural;
    for (std::size_t i = 0; i < count; ++i) natural.push_back(space.ToNatural(nests[i]));
    std::vector<double> v = EvaluateInParallel(objective, natural, threads);
    v.resize(nests.size(), std::numeric_limits<double>::infinity());
    summary.evaluations += static_cast<long>(count);
    return v;
  };

  // Initial nests: uniform within the bounds (in the searched coordinates).
  std::vector<std::vector<double>> nest(n, std::vector<double>(dim));
  for (auto& x : nest)
    for (std::size_t j = 0; j < dim; ++j) x[j] = space.lo[j] + (space.hi[j] - space.lo[j]) * uniform(rng);
  std::vector<double> fitness = evaluate(nest);
  std::size_t best = std::min_element(fitness.begin(), fitness.end()) - fitness.begin();
  std::vector<double> best_z = nest[best];
  double best_value = fitness[best];
  summary.best_value_history.push_back(best_value);

  const double beta = options.levy_beta;
  const double sigma_u = MantegnaSigma(beta);
  auto accept = [&](std::vector<std::vector<double>>& cand, const std::vector<double>& v) {
    for (int i = 0; i < n; ++i) {
      if (v[i] <= fitness[i]) {  // greedy replacement, nest order
        nest[i] = std::move(cand[i]);
        fitness[i] = v[i];
      }
    }
    best = std::min_element(fitness.begin(), fitness.end()) - fitness.begin();
    if (fitness[best] <= best_value) {
      best_value = fitness[best];
      best_z = nest[best];
    }
  };
  auto done = [&] {
    if (options.target_value && best_value <= *options.target_value) {
      summary.termination = CuckooTermination::kTargetReached;
      return true;
    }
    if (summary.evaluations >= max_evals) {
      summary.termination = CuckooTermination::kMaxEvaluations;
      return true;
    }
    return false;
  };

  for (int gen = 0; gen < options.max_generations && !done(); ++gen) {
    // 1. Levy flights (Eq. 24): x' = x + alpha * L .* (x - best) .* N(0, 1), L by Mantegna:
    //    L = u / |v|^(1/beta), u ~ N(0, sigma_u^2), v ~ N(0, 1).
    std::vector<std::vector<double>> cand = nest;
    for (int i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < dim; ++j) {
        const double u = gauss(rng) * sigma_u;
        const double v = gauss(rng);
        const double levy = u / std::pow(std::abs(v), 1.0 / beta);
        const double step = options.step_scale * levy * (nest[i][j] - best_z[j]);
        cand[i][j] += step * gauss(rng);
      }
      space.Clip(cand[i]);
    }
    accept(cand, evaluate(cand));
    if (done()) {
      summary.generations = gen + 1;
      summary.best_value_history.push_back(best_value);
      if (options.on_generation) options.on_generation(gen + 1, best_value);
      break;
    }
    // 2. Discovery with probability pa: x'' = x + r * (x_p - x_q) on the discovered components.
    std::vector<int> p(n), q(n);
    std::iota(p.begin(), p.end(), 0);
    std::iota(q.begin(), q.end(), 0);
    std::shuffle(p.begin(), p.end(), rng);
    std::shuffle(q.begin(), q.end(), rng);
    cand = nest;
    for (int i = 0; i < n; ++i) {
      const double r = uniform(rng);
      for (std::size_t j = 0; j < dim; ++j) {
        if (uniform(rng) > options.discovery_probability)
          cand[i][j] += r * (nest[p[i]][j] - nest[q[i]][j]);
      }
      space.Clip(cand[i]);
    }
    accept(cand, evaluate(cand));
    summary.generations = gen + 1;
    summary.best_value_history.push_back(best_value);
    if (options.on_generation) options.on_generation(gen + 1, best_value);
  }
  if (summary.termination == CuckooTermination::kMaxGenerations) done();  // record the reason

  summary.best_x = space.ToNatural(best_z);
  summary.best_value = best_value;
  summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return summary;
}

}  // namespace gyrocomp
