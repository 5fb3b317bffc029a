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
#include <utility>

#include "gyrocomp/core/format.h"

namespace gyrocomp {
namespace {

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
    return fail("discovery_probability = " + FormatNumber(discovery_probability) + ": must be in [0, 1]");
  if (!(levy_beta > 0.0 && levy_beta <= 2.0))
    return fail("levy_beta = " + FormatNumber(levy_beta) + ": must be in (0, 2]");
  if (!(step_scale > 0.0) || !std::isfinite(step_scale))
    return fail("step_scale = " + FormatNumber(step_scale) + ": must be > 0");
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
                                       int num_threads,
                                       const CancellationToken* cancel) {
  std::vector<double> values(points.size(), std::numeric_limits<double>::infinity());
  const int workers = std::max(1, std::min<int>(num_threads, static_cast<int>(points.size())));
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stopped{false};  // an objective threw Cancelled (e.g. SvrOptions::cancel)
  auto cancelled = [&] { return stopped || (cancel != nullptr && cancel->cancelled()); };
  auto work = [&] {
    try {
      for (std::size_t i = next++; i < points.size() && !cancelled(); i = next++)
        values[i] = Sanitize(objective(points[i]));
    } catch (const Cancelled&) {  // not past a worker thread: thrown again below
      stopped = true;
    }
  };
  if (workers == 1) {
    work();
  } else {
    std::vector<std::thread> threads;
    for (int t = 1; t < workers; ++t) threads.emplace_back(work);
    work();
    for (auto& th : threads) th.join();
  }
  if (cancelled()) throw Cancelled();  // on the calling thread, after the workers joined
  return values;
}

namespace {

// The searched space of `dimensions` (log10 coordinates where log_scale), or an error naming
// the dimension at fault.
Result<Space> MakeSpace(std::span<const SearchDimension> dimensions) {
  Space space;
  for (const SearchDimension& d : dimensions) {
    const std::string name = "SearchDimension '" + d.name + "'";
    if (!std::isfinite(d.lower) || !std::isfinite(d.upper) || !(d.lower < d.upper))
      return InvalidArgument(name + ": bounds [" + FormatNumber(d.lower) + ", " + FormatNumber(d.upper) +
                             "]: need finite lower < upper");
    if (d.log_scale && !(d.lower > 0.0))
      return InvalidArgument(name + ": log_scale needs lower > 0, got " + FormatNumber(d.lower));
    space.lo.push_back(d.log_scale ? std::log10(d.lower) : d.lower);
    space.hi.push_back(d.log_scale ? std::log10(d.upper) : d.upper);
    space.log.push_back(d.log_scale);
  }
  return space;
}

using Nests = std::vector<std::vector<double>>;

// The state of one search: the nests, their values, the best so far, the random generator (all
// draws happen here, in one thread, in a fixed order) and the summary being filled in.
class CuckooRun {
 public:
  CuckooRun(const SearchObjective& objective, Space space, std::size_t dim, const CuckooSearchOptions& options)
      : objective_(objective),
        space_(std::move(space)),
        dim_(dim),
        opt_(options),
        n_(options.num_nests),
        max_evals_(options.max_evaluations.value_or(std::numeric_limits<long>::max())),
        rng_(options.seed),
        sigma_u_(MantegnaSigma(options.levy_beta)) {
    int threads = options.num_threads.value_or(static_cast<int>(std::thread::hardware_concurrency()));
    threads = std::max(1, threads);
    summary_.num_threads = threads;
  }

  // Initial nests: uniform within the bounds (in the searched coordinates).
  void InitialNests() {
    nest_.assign(n_, std::vector<double>(dim_));
    for (auto& x : nest_)
      for (std::size_t j = 0; j < dim_; ++j) x[j] = space_.lo[j] + (space_.hi[j] - space_.lo[j]) * uniform_(rng_);
    fitness_ = Evaluate(nest_);
    best_ = std::min_element(fitness_.begin(), fitness_.end()) - fitness_.begin();
    best_z_ = nest_[best_];
    best_value_ = fitness_[best_];
    summary_.best_value_history.push_back(best_value_);
  }

  // Step 1, Levy flights (Eq. 24): x' = x + alpha * L .* (x - best) .* N(0, 1), L by Mantegna:
  // L = u / |v|^(1/beta), u ~ N(0, sigma_u^2), v ~ N(0, 1).
  Nests LevyFlights() {
    const double beta = opt_.levy_beta;
    Nests cand = nest_;
    for (int i = 0; i < n_; ++i) {
      for (std::size_t j = 0; j < dim_; ++j) {
        const double u = gauss_(rng_) * sigma_u_;
        const double v = gauss_(rng_);
        const double levy = u / std::pow(std::abs(v), 1.0 / beta);
        const double step = opt_.step_scale * levy * (nest_[i][j] - best_z_[j]);
        cand[i][j] += step * gauss_(rng_);
      }
      space_.Clip(cand[i]);
    }
    return cand;
  }

  // Step 2, discovery with probability pa: x'' = x + r * (x_p - x_q) on the discovered
  // components (those where U(0,1) > pa, as in the reference code).
  Nests Discovery() {
    std::vector<int> p(n_), q(n_);
    std::iota(p.begin(), p.end(), 0);
    std::iota(q.begin(), q.end(), 0);
    std::shuffle(p.begin(), p.end(), rng_);
    std::shuffle(q.begin(), q.end(), rng_);
    Nests cand = nest_;
    for (int i = 0; i < n_; ++i) {
      const double r = uniform_(rng_);
      for (std::size_t j = 0; j < dim_; ++j) {
        if (uniform_(rng_) > opt_.discovery_probability)
          cand[i][j] += r * (nest_[p[i]][j] - nest_[q[i]][j]);
      }
      space_.Clip(cand[i]);
    }
    return cand;
  }

  // Evaluates the candidates and keeps each one that is no worse than its nest.
  void Replace(Nests& cand) { Accept(cand, Evaluate(cand)); }

  // True (and the reason recorded) once the target or the evaluation budget is reached.
  bool Done() {
    if (opt_.target_value && best_value_ <= *opt_.target_value) {
      summary_.termination = CuckooTermination::kTargetReached;
      return true;
    }
    if (summary_.evaluations >= max_evals_) {
      summary_.termination = CuckooTermination::kMaxEvaluations;
      return true;
    }
    return false;
  }

  // Records generation `generation` (1-based) as complete.
  void EndGeneration(int generation) {
    summary_.generations = generation;
    summary_.best_value_history.push_back(best_value_);
    if (opt_.on_generation) opt_.on_generation(generation, best_value_);
  }

  CuckooSearchSummary Finish(std::chrono::steady_clock::time_point t0) {
    if (summary_.termination == CuckooTermination::kMaxGenerations) Done();  // record the reason
    summary_.best_x = space_.ToNatural(best_z_);
    summary_.best_value = best_value_;
    summary_.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return std::move(summary_);
  }

 private:
  // Evaluates up to the remaining budget; candidates beyond it are not evaluated (value +inf).
  std::vector<double> Evaluate(const Nests& nests) {
    const long left = max_evals_ - summary_.evaluations;
    const std::size_t count = static_cast<std::size_t>(std::min<long>(left, static_cast<long>(nests.size())));
    Nests natural;
    for (std::size_t i = 0; i < count; ++i) natural.push_back(space_.ToNatural(nests[i]));
    std::vector<double> v = EvaluateInParallel(objective_, natural, summary_.num_threads, opt_.cancel);
    v.resize(nests.size(), std::numeric_limits<double>::infinity());
    summary_.evaluations += static_cast<long>(count);
    return v;
  }

  void Accept(Nests& cand, const std::vector<double>& v) {
    for (int i = 0; i < n_; ++i) {
      if (v[i] <= fitness_[i]) {  // greedy replacement, nest order
        nest_[i] = std::move(cand[i]);
        fitness_[i] = v[i];
      }
    }
    best_ = std::min_element(fitness_.begin(), fitness_.end()) - fitness_.begin();
    if (fitness_[best_] <= best_value_) {
      best_value_ = fitness_[best_];
      best_z_ = nest_[best_];
    }
  }

  const SearchObjective& objective_;
  Space space_;
  std::size_t dim_;
  const CuckooSearchOptions& opt_;
  int n_;
  long max_evals_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  std::normal_distribution<double> gauss_{0.0, 1.0};
  double sigma_u_;
  CuckooSearchSummary summary_;
  Nests nest_;
  std::vector<double> fitness_;
  std::size_t best_ = 0;
  std::vector<double> best_z_;
  double best_value_ = 0.0;
};

}  // namespace

Result<CuckooSearchSummary> CuckooSearch(const SearchObjective& objective,
                                         std::span<const SearchDimension> dimensions,
                                         const CuckooSearchOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (dimensions.empty()) return InvalidArgument("CuckooSearch: no dimensions to search");
  Result<Space> space = MakeSpace(dimensions);
  if (!space) return space.error();

  CuckooRun run(objective, std::move(*space), dimensions.size(), options);
  run.InitialNests();
  for (int gen = 0; gen < options.max_generations && !run.Done(); ++gen) {
    // 1. Levy flights (Eq. 24), each new egg replacing its nest if no worse.
    Nests cand = run.LevyFlights();
    run.Replace(cand);
    if (run.Done()) {
      run.EndGeneration(gen + 1);
      break;
    }
    // 2. Discovery of a fraction of the components (abandon probability pa), then replacement.
    cand = run.Discovery();
    run.Replace(cand);
    run.EndGeneration(gen + 1);
  }
  return run.Finish(t0);
}

}  // namespace gyrocomp
