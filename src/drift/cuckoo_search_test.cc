#include "gyrocomp/drift/cuckoo_search.h"
#include "optimization_test_functions.h"

#include <atomic>
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

namespace gyrocomp {
namespace {

using test_functions::Ackley;
using test_functions::Rastrigin;
using test_functions::Rosenbrock;
using test_functions::Sphere;

std::vector<SearchDimension> Box(int d, double lo, double hi) {
  return std::vector<SearchDimension>(d, SearchDimension{"x", lo, hi, false});
}

struct Case {
  const char* name;
  double (*f)(std::span<const double>);
  int dims;
  double lo, hi;
  int generations;       // budget: 25 nests * (1 + 2 * generations) evaluations
  double tolerance;      // on f(best) - f(optimum) = f(best): all optima are 0
  std::vector<double> optimum;
};

// Standard functions, standard domains, Yang & Deb's settings (25 nests, pa 0.25, beta 1.5,
// step 0.01). Budget = 25 * (1 + 2 * generations) evaluations. Tolerances: a sweep over seeds
// 1..30 gave worst-case best values sphere2 2.8e-12, sphere10 6.5e-17,
// rosenbrock2 1.7e-7, rosenbrock5 9.8e-15, rastrigin2 1.0e-7, rastrigin5 6.1e-5, ackley2 2.2e-6,
// ackley10 8.3e-10; each tolerance is 16 to 1e5 times that worst case, yet far below the
// nearest local minima (Rastrigin about 0.99, Ackley above 1), so landing in a local minimum or a
// broken Levy / discovery step fails. Each case also checks the location of the optimum.
class StandardFunctions : public ::testing::TestWithParam<Case> {};

TEST_P(StandardFunctions, ReachesKnownOptimum) {
  const Case& c = GetParam();
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    CuckooSearchOptions o;
    o.max_generations = c.generations;
    o.seed = seed;
    auto dims = Box(c.dims, c.lo, c.hi);
    auto r = CuckooSearch(c.f, dims, o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->evaluations, 25L * (1 + 2 * c.generations));
    EXPECT_LE(r->best_value, c.tolerance) << c.name << " seed " << seed << ": " << r->BriefReport();
    // The best point is near the optimum: within the distance the tolerance allows for a
    // quadratic bowl of unit curvature, or 0.05, whichever is larger.
    for (int j = 0; j < c.dims; ++j)
      EXPECT_NEAR(r->best_x[j], c.optimum[j], std::max(0.05, 2.0 * std::sqrt(c.tolerance)))
          << c.name << " seed " << seed << " x[" << j << "]";
    // The history is non-increasing (the best is never lost).
    for (std::size_t g = 1; g < r->best_value_history.size(); ++g)
      EXPECT_LE(r->best_value_history[g], r->best_value_history[g - 1]);
  }
}

INSTANTIATE_TEST_SUITE_P(
    CuckooSearch, StandardFunctions,
    ::testing::Values(Case{"sphere2", Sphere, 2, -5.12, 5.12, 200, 1e-10, {0, 0}},
                      Case{"sphere10", Sphere, 10, -5.12, 5.12, 1000, 1e-12, std::vector<double>(10, 0.0)},
                      Case{"rosenbrock2", Rosenbrock, 2, -5.0, 10.0, 400, 1e-5, {1, 1}},
                      Case{"rosenbrock5", Rosenbrock, 5, -5.0, 10.0, 2000, 1e-10, std::vector<double>(5, 1.0)},
                      Case{"rastrigin2", Rastrigin, 2, -5.12, 5.12, 300, 1e-5, {0, 0}},
                      Case{"rastrigin5", Rastrigin, 5, -5.12, 5.12, 1000, 1e-3, std::vector<double>(5, 0.0)},
                      Case{"ackley2", Ackley, 2, -32.768, 32.768, 300, 1e-4, {0, 0}},
                      Case{"ackley10", Ackley, 10, -32.768, 32.768, 1500, 1e-7, std::vector<double>(10, 0.0)}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

// Same seed -> bit-identical result, whatever the number of threads.
TEST(CuckooSearch, DeterministicRegardlessOfThreads) {
  auto dims = Box(3, -5.0, 5.0);
  CuckooSearchOptions o;
  o.max_generations = 30;
  o.seed = 42;
  o.num_threads = 1;
  auto a = CuckooSearch(Rastrigin, dims, o);
  o.num_threads = 4;
  auto b = CuckooSearch(Rastrigin, dims, o);
  o.num_threads = 7;
  auto c = CuckooSearch(Rastrigin, dims, o);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_EQ(a->best_x, b->best_x);
  EXPECT_EQ(a->best_x, c->best_x);
  EXPECT_EQ(a->best_value_history, b->best_value_history);
  o.seed = 43;
  auto d = CuckooSearch(Rastrigin, dims, o);
  ASSERT_TRUE(d.ok());
  EXPECT_NE(a->best_x, d->best_x);
}

// Log-space dimensions: the objective receives natural values within the bounds, and a minimum
// spread over decades (at x = 1e-3 in [1e-6, 1e2]) is found.
TEST(CuckooSearch, LogScaleDimension) {
  std::atomic<bool> out_of_bounds{false};
  auto f = [&](std::span<const double> x) {
    if (x[0] < 1e-6 || x[0] > 1e2) out_of_bounds = true;
    const double l = std::log10(x[0]) + 3.0;
    return l * l;
  };
  const std::vector<SearchDimension> dims = {{"C", 1e-6, 1e2, true}};
  CuckooSearchOptions o;
  o.max_generations = 100;
  auto r = CuckooSearch(f, dims, o);
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(out_of_bounds);
  EXPECT_NEAR(std::log10(r->best_x[0]), -3.0, 1e-4);  // f = 1e-8 reached easily in 1-D
}

TEST(CuckooSearch, BudgetTargetAndNonFinite) {
  auto dims = Box(2, -5.0, 5.0);
  CuckooSearchOptions o;
  o.max_generations = 1000;
  o.max_evaluations = 300;
  auto r = CuckooSearch(Sphere, dims, o);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->evaluations, 300);
  EXPECT_EQ(r->termination, CuckooTermination::kMaxEvaluations);

  o.max_evaluations.reset();
  o.target_value = 1e-3;
  r = CuckooSearch(Sphere, dims, o);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->termination, CuckooTermination::kTargetReached);
  EXPECT_LE(r->best_value, 1e-3);
  EXPECT_LT(r->generations, 1000);

  // NaN where x[0] < 0 counts as +inf: the search stays in x[0] >= 0.
  auto g = [](std::span<const double> x) { return x[0] < 0 ? std::nan("") : Sphere(x); };
  o.target_value.reset();
  o.max_generations = 50;
  r = CuckooSearch(g, dims, o);
  ASSERT_TRUE(r.ok());
  EXPECT_GE(r->best_x[0], 0.0);
  EXPECT_TRUE(std::isfinite(r->best_value));
}

TEST(CuckooSearch, RejectsBadOptions) {
  auto dims = Box(2, -1.0, 1.0);
  CuckooSearchOptions o;
  o.discovery_probability = 1.5;
  auto r = CuckooSearch(Sphere, dims, o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "CuckooSearchOptions::discovery_probability = 1.5: must be in [0, 1]");
  o = CuckooSearchOptions{};
  const std::vector<SearchDimension> bad = {{"C", 0.0, 10.0, true}};
  r = CuckooSearch(Sphere, bad, o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().kind, ErrorKind::kInvalidArgument);
  EXPECT_NE(r.error().message.find("'C'"), std::string::npos);
}

// A cancel is honoured between evaluations, not only between generations: no new
// parameter set starts once the token is cancelled, and the search throws Cancelled.
TEST(CuckooSearchCancel, StopsWithinAGenerationAndThrows) {
  CancellationToken token;
  std::atomic<int> calls{0};
  const SearchObjective objective = [&](std::span<const double> p) {
    if (++calls == 7) token.Cancel();
    return p[0] * p[0];
  };
  CuckooSearchOptions o;
  o.num_nests = 25;
  o.max_generations = 50;
  o.num_threads = 2;
  o.cancel = &token;
  const SearchDimension x{"x", -1.0, 1.0, false};
  EXPECT_THROW((void)CuckooSearch(objective, std::span<const SearchDimension>(&x, 1), o), Cancelled);
  // The cancelling call and at most one running on the other thread.
  EXPECT_LE(calls.load(), 8);
}

}  // namespace
}  // namespace gyrocomp
