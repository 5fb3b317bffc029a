// The two fast counters of sample entropy forced one at a time (kRangeCount, kSortedWindow)
// against the brute-force definition and the antropy golden values, and the pieces of the
// sorted window (sample_entropy_window.h). kFast picks one of them per series, so each must be
// exact on its own, ties at distance r included.
#include "sample_entropy_window.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "gyrocomp/decompose/sample_entropy.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

using testing::GoldenPath;
using testing::ReadGoldenCsv;
using testing::ReadJsonFile;

constexpr SampleEntropyAlgorithm kForced[] = {SampleEntropyAlgorithm::kRangeCount,
                                              SampleEntropyAlgorithm::kSortedWindow};

std::string Name(SampleEntropyAlgorithm a) {
  return a == SampleEntropyAlgorithm::kRangeCount ? "range" : a == SampleEntropyAlgorithm::kSortedWindow ? "window"
                                                                                                          : "other";
}

struct Series {
  std::string name;
  std::vector<double> x;
};

// Continuous, quantized (distances equal to r occur), few levels (long runs of ties), smooth
// (almost every pair matches), a narrow-band VMD-like mode, and values of both signs around 0
// including -0.0 and +0.0.
std::vector<Series> SeriesInputs(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, 1);
  std::vector<Series> s = {{"white", {}}, {"quantized", {}}, {"few_levels", {}}, {"smooth", {}},
                           {"narrow_band", {}}, {"signed_zeros", {}}};
  double phase = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double v = g(rng);
    s[0].x.push_back(v);
    s[1].x.push_back(std::round(v * 0.1 / 0.05) * 0.05);
    s[2].x.push_back(static_cast<double>(rng() % 3));
    s[3].x.push_back(std::sin(2 * std::numbers::pi * 0.004 * i) + 0.01 * v);
    phase += 2 * std::numbers::pi * 0.2 + 0.05 * g(rng);
    s[4].x.push_back(std::cos(phase));
    const int level = static_cast<int>(rng() % 5) - 2;  // -2..2, zeros of either sign
    s[5].x.push_back(level == 0 ? ((rng() & 1) ? -0.0 : 0.0) : 0.25 * level);
  }
  return s;
}

TEST(SampleEntropyCounters, EachCounterEqualsBruteForce) {
  for (unsigned seed : {1u, 2u}) {
    for (std::size_t n : {3u, 4u, 9u, 17u, 30u, 257u, 1000u}) {
      for (const Series& c : SeriesInputs(n, seed)) {
        const double sd = PopulationSd(c.x);
        for (int m : {1, 2, 3, 4, 5}) {
          if (n < static_cast<std::size_t>(m) + 2) continue;
          // Relative tolerances and absolute ones that are multiples of the quantization steps.
          for (double r : {0.1 * sd, 0.2 * sd, 0.5 * sd, 3.0 * sd, 0.05, 0.25, 1.0}) {
            if (!(r > 0)) continue;
            const auto brute = CountTemplateMatches(c.x, m, r, SampleEntropyAlgorithm::kBruteForce);
            for (SampleEntropyAlgorithm a : kForced) {
              const auto got = CountTemplateMatches(c.x, m, r, a, 1);
              EXPECT_EQ(got.a, brute.a) << Name(a) << " " << c.name << " n=" << n << " m=" << m << " r=" << r;
              EXPECT_EQ(got.b, brute.b) << Name(a) << " " << c.name << " n=" << n << " m=" << m << " r=" << r;
            }
          }
        }
      }
    }
  }
}

TEST(SampleEntropyCounters, EachCounterMatchesAntropyGoldenValues) {
  const auto meta = ReadJsonFile(GoldenPath("sample_entropy/sample_entropy.json"));
  const auto signals = ReadGoldenCsv(GoldenPath("sample_entropy/signals.csv"));
  int checked = 0;
  for (const auto& c : meta.at("cases")) {
    SampleEntropyOptions opt;
    opt.m = c.at("m").get<int>();
    opt.r_factor = c.at("r_factor").get<double>();
    for (SampleEntropyAlgorithm a : kForced) {
      SCOPED_TRACE(c.at("signal").get<std::string>() + " m=" + std::to_string(opt.m) + " " + Name(a));
      opt.algorithm = a;
      auto r = SampleEntropy(signals.at(c.at("signal").get<std::string>()), opt);
      ASSERT_TRUE(r.ok()) << r.error().message;
      // 1e-12 as in sample_entropy_test.cc: equal counts give -ln(A/B) to the last bits of log().
      EXPECT_NEAR(r->sample_entropy, c.at("sample_entropy").get<double>(), 1e-12);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 90);
}

TEST(SampleEntropyCounters, WindowThreadCountDoesNotChangeCounts) {
  // 30,000 samples: slices of more than 1024 templates per thread, so 2 and 3 threads split.
  for (const Series& c : SeriesInputs(30000, 4)) {
    if (c.name == "few_levels" || c.name == "signed_zeros") continue;  // W ~ N^2 / 6: slow, not new
    const double r = 0.2 * PopulationSd(c.x);
    const auto one = CountTemplateMatches(c.x, 2, r, SampleEntropyAlgorithm::kSortedWindow, 1);
    for (int threads : {2, 3}) {
      const auto more = CountTemplateMatches(c.x, 2, r, SampleEntropyAlgorithm::kSortedWindow, threads);
      EXPECT_EQ(more.a, one.a) << c.name << " threads=" << threads;
      EXPECT_EQ(more.b, one.b) << c.name << " threads=" << threads;
    }
    const auto range = CountTemplateMatches(c.x, 2, r, SampleEntropyAlgorithm::kRangeCount, 2);
    EXPECT_EQ(range.a, one.a) << c.name;
    EXPECT_EQ(range.b, one.b) << c.name;
    EXPECT_GT(one.a, 0u) << c.name;
  }
}

TEST(SampleEntropyCounters, EveryKernelPathGivesTheBruteForceCounts) {
  // The dispatched variants (AVX-512BW, AVX2, x86-64 baseline) that this CPU runs; both layouts
  // (strip: smooth, narrow band; cells: white) and every m, tails of every length (n = 1000).
  int paths_run = 0;
  for (auto path : {se_detail::WindowPath::kAvx512bw, se_detail::WindowPath::kAvx2, se_detail::WindowPath::kBaseline}) {
    if (!se_detail::WindowPathSupported(path)) continue;
    ++paths_run;
    for (const Series& c : SeriesInputs(1000, 6)) {
      const std::vector<std::uint32_t> order = se_detail::OrderByValue(c.x);
      for (int m = 1; m <= se_detail::kWindowMaxM; ++m) {
        const double r = 0.3 * PopulationSd(c.x);
        const auto plan = se_detail::PlanWindow(c.x, order, c.x.size() - m, m, r);
        ASSERT_TRUE(plan.narrow);  // 16-bit ranks here; 32-bit: the test below
        const auto got = se_detail::CountWindowed(plan, 2, path);
        const auto brute = CountTemplateMatches(c.x, m, r, SampleEntropyAlgorithm::kBruteForce);
        EXPECT_EQ(got.a, brute.a) << c.name << " m=" << m << " path " << static_cast<int>(path);
        EXPECT_EQ(got.b, brute.b) << c.name << " m=" << m << " path " << static_cast<int>(path);
      }
    }
  }
  EXPECT_GE(paths_run, 1);
}

TEST(SampleEntropyCounters, WideRanksAboveSixtyFiveThousandDistinctValues) {
  // 70,000 distinct values: 32-bit ranks (16-bit up to 65,536). Against range counting (the
  // brute force would take minutes), on every kernel path, both layouts, m = 1..3.
  for (const Series& c : SeriesInputs(70000, 8)) {
    if (c.name != "white" && c.name != "narrow_band" && c.name != "smooth") continue;
    const std::vector<std::uint32_t> order = se_detail::OrderByValue(c.x);
    for (int m = 1; m <= 3; ++m) {
      const double r = 0.1 * PopulationSd(c.x);
      const auto plan = se_detail::PlanWindow(c.x, order, c.x.size() - m, m, r);
      ASSERT_FALSE(plan.narrow) << c.name;
      const auto range = CountTemplateMatches(c.x, m, r, SampleEntropyAlgorithm::kRangeCount, 2);
      for (auto path :
           {se_detail::WindowPath::kAvx512bw, se_detail::WindowPath::kAvx2, se_detail::WindowPath::kBaseline}) {
        if (!se_detail::WindowPathSupported(path)) continue;
        const auto got = se_detail::CountWindowed(plan, 2, path);
        EXPECT_EQ(got.a, range.a) << c.name << " m=" << m << " path " << static_cast<int>(path);
        EXPECT_EQ(got.b, range.b) << c.name << " m=" << m << " path " << static_cast<int>(path);
      }
    }
  }
}

TEST(SampleEntropyCounters, OrderByValueSortsEverySignAndScale) {
  std::vector<double> x = {3.0, -0.0, 0.0, -1e308, 1e308, 5e-324, -5e-324, -2.5, 2.5, 0.0, -0.0,
                           std::numeric_limits<double>::min(), -std::numeric_limits<double>::max(), 1.0, 1.0};
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0, 1e3);
  for (int i = 0; i < 5000; ++i) x.push_back(std::ldexp(g(rng), static_cast<int>(rng() % 200) - 100));
  const std::vector<std::uint32_t> order = se_detail::OrderByValue(x);
  ASSERT_EQ(order.size(), x.size());
  std::vector<std::uint32_t> seen(order);
  std::sort(seen.begin(), seen.end());
  for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], i) << "not a permutation";
  for (std::size_t k = 1; k < order.size(); ++k) {
    ASSERT_LE(x[order[k - 1]], x[order[k]]) << "position " << k;
  }
  EXPECT_TRUE(se_detail::OrderByValue({}).empty());
}

TEST(SampleEntropyCounters, PlanKeepsTheLayoutWithFewerChecks) {
  // m = 1, r = 1: values 1 0 3 0.5 1; templates 0..3 (values 1 0 3 0.5) sorted 0 0.5 1 3.
  // Strip: pairs within r in the first value: (0, 0.5), (0.5, 1) = 2 pairs of 1 check (the second
  // value). Cells: groups {0, 0.5} {1} {3} (1 - 0 = r is not within), cells 1 0 2 0: run 1 holds
  // (0, 0.5), run 2 the 3 pairs with the next group, 1 + 3 x 2 = 7 checks. The strip is kept.
  const std::vector<double> x = {1, 0, 3, 0.5, 1};
  const std::vector<std::uint32_t> order = se_detail::OrderByValue(x);
  const auto strip = se_detail::PlanWindow(x, order, 4, 1, 1.0);
  EXPECT_EQ(strip.pairs, 2u);
  EXPECT_EQ(strip.coordinate_checks, 2u);
  EXPECT_EQ(se_detail::PlanWindow(x, order, 4, 1, 10.0).pairs, 6u);  // one group: every pair
  // White noise, r = 0.2 SD, m = 2: the cells keep ~3% of the N^2 / 2 pairs (the strip of the
  // first value alone ~11%): a property of the plan, not a timing.
  const Series white = SeriesInputs(20000, 3)[0];
  const auto plan = se_detail::PlanWindow(white.x, se_detail::OrderByValue(white.x), 19998, 2,
                                          0.2 * PopulationSd(white.x));
  EXPECT_LT(plan.pairs, 500u * 19998u);
  EXPECT_GT(plan.pairs, 100u * 19998u);
}

}  // namespace
}  // namespace gyrocomp
