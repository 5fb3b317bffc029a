// Cuckoo search (Yang & Deb 2009; paper Section 3.4, Eq. 24): a general bounded minimiser.
//
// Each generation, as in Yang & Deb's reference code:
//   1. every nest lays a cuckoo by a Levy flight (Eq. 24): x' = x + step_scale * L * (x - best)
//      .* N(0,1), L drawn by Mantegna's algorithm with exponent beta; x' replaces x if better;
//   2. discovery: x'' = x + r * (x_p - x_q), r ~ U(0,1) per nest, p and q two random
//      permutations, applied to the components where U(0,1) > pa (exactly as the reference
//      cuckoo_search.m: K = rand(n,d) > pa; the literal reading "changed with probability pa"
//      ended 10^3-10^5 times worse on the standard functions); x'' replaces x if better.
// That is 2 * num_nests evaluations per generation (plus num_nests at the start). Candidates are
// clipped to the bounds. A dimension marked log_scale is searched in log10 space (its bounds must
// then be > 0); the objective always receives the values in natural units.
//
// Determinism: all random numbers are drawn in one thread, in a fixed order, from a generator
// seeded by `seed`; the candidates of a step are then evaluated in parallel and selected in nest
// order. The result depends on the seed only, never on the number of threads.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyrocomp/core/cancel.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp {

// One searched parameter: its name and bounds.
struct SearchDimension {
  std::string name;        // for messages and reports ("C", "sigma")
  double lower = 0.0;      // natural units, lower < upper
  double upper = 1.0;  // natural units, > lower
  bool log_scale = false;  // search log10(x) uniformly; requires lower > 0
};

// Cuckoo search settings (Yang & Deb 2009, Levy flights by Mantegna's algorithm).
struct CuckooSearchOptions {
  // Number of nests n (Yang & Deb: 25; also the paper's method.md default).
  int num_nests = 25;
  // Discovery probability pa in [0, 1] (Yang & Deb: 0.25).
  double discovery_probability = 0.25;
  // Levy exponent beta in (0, 2] for Mantegna's algorithm (Yang & Deb: 1.5).
  double levy_beta = 1.5;
  // Step scale alpha of the Levy flight, relative to (x - best) (Yang & Deb: 0.01).
  double step_scale = 0.01;
  // Generations to run (each = 2 * num_nests evaluations).
  int max_generations = 100;
  // Optional hard cap on objective evaluations (the initial nests count).
  std::optional<long> max_evaluations;
  // Optional early stop once the best value is <= this.
  std::optional<double> target_value;
  // Seed of the random generator (std::mt19937_64).
  std::uint64_t seed = 1;
  // Threads evaluating nests in parallel; automatic = std::thread::hardware_concurrency().
  std::optional<int> num_threads;
  // Called after every generation with its number (1-based) and the best value so far, from the
  // calling thread (progress displays). Empty: not called. Does not change the result.
  std::function<void(int generation, double best_value)> on_generation;
  // Polled before every evaluation: once cancelled, no new parameter set is started,
  // the ones running finish, and CuckooSearch throws Cancelled on the calling thread. nullptr:
  // not polled. Not owned.
  const CancellationToken* cancel = nullptr;

  // False with the field, its value and the rule in `error` when a setting is out of range.
  bool IsValid(std::string* error) const;
};

// Why the search stopped.
enum class CuckooTermination { kMaxGenerations, kMaxEvaluations, kTargetReached };
// "max generations" | "max evaluations" | "target reached", for reports.
const char* CuckooTerminationName(CuckooTermination t);

// What a cuckoo search found and how it ran.
struct CuckooSearchSummary {
  std::vector<double> best_x;           // natural units
  double best_value = 0.0;  // objective at best_x
  int generations = 0;  // generations run
  long evaluations = 0;  // objective evaluations, the initial nests included
  int num_threads = 1;  // threads used
  CuckooTermination termination = CuckooTermination::kMaxGenerations;  // why it stopped
  std::vector<double> best_value_history;  // best after the init and after each generation
  double time_s = 0.0;  // wall time, s
  // One line for logs: best value and point, generations, evaluations, threads, why it stopped, time.
  std::string BriefReport() const;
};

// Objective to minimise. Called concurrently from several threads: it must be thread-safe and
// must not depend on call order. Non-finite values count as +infinity.
using SearchObjective = std::function<double(std::span<const double> x)>;

// Errors: invalid options or dimensions (kInvalidArgument).
Result<CuckooSearchSummary> CuckooSearch(const SearchObjective& objective,
                                         std::span<const SearchDimension> dimensions,
                                         const CuckooSearchOptions& options);

// Evaluates `points` (natural units) with `objective` on `num_threads` threads; results in order.
// Shared by cuckoo search and the grid-search baseline.
std::vector<double> EvaluateInParallel(const SearchObjective& objective,
                                       const std::vector<std::vector<double>>& points,
                                       int num_threads,
                                       const CancellationToken* cancel = nullptr);

}  // namespace gyrocomp
