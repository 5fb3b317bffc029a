// Cuckoo search on the standard functions of cuckoo_search_test.cc over 30 seeds: time per run
// and the worst / best final value reached (the sweep behind the test tolerances).
//   ./cuckoo_search_benchmark
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "gyrocomp/drift/cuckoo_search.h"
#include "optimization_test_functions.h"

namespace gyrocomp {
namespace {

using test_functions::Ackley;
using test_functions::Rastrigin;
using test_functions::Rosenbrock;
using test_functions::Sphere;

void Sweep(benchmark::State& state, double (*f)(std::span<const double>), int dims, double lo, double hi,
           int generations) {
  double worst = 0.0, best = std::numeric_limits<double>::infinity();
  for (auto _ : state) {
    for (std::uint64_t seed = 1; seed <= 30; ++seed) {
      CuckooSearchOptions o;
      o.max_generations = generations;
      o.seed = seed;
      o.num_threads = 1;  // the functions are too cheap for threads to pay
      const std::vector<SearchDimension> d(dims, SearchDimension{"x", lo, hi, false});
      auto r = CuckooSearch(f, d, o);
      worst = std::max(worst, r->best_value);
      best = std::min(best, r->best_value);
    }
  }
  state.counters["worst_of_30"] = worst;
  state.counters["best_of_30"] = best;
  state.counters["evaluations"] = 25.0 * (1 + 2 * generations);
}

BENCHMARK_CAPTURE(Sweep, sphere2, Sphere, 2, -5.12, 5.12, 200)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Sweep, sphere10, Sphere, 10, -5.12, 5.12, 1000)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Sweep, rosenbrock2, Rosenbrock, 2, -5.0, 10.0, 400)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Sweep, rosenbrock5, Rosenbrock, 5, -5.0, 10.0, 2000)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Sweep, rastrigin2, Rastrigin, 2, -5.12, 5.12, 300)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Sweep, rastrigin5, Rastrigin, 5, -5.12, 5.12, 1000)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Sweep, ackley2, Ackley, 2, -32.768, 32.768, 300)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Sweep, ackley10, Ackley, 10, -32.768, 32.768, 1500)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace gyrocomp
