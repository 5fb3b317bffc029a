#include "gyrocomp/decompose/sample_entropy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "test_support.h"

namespace gyrocomp {
namespace {

using testing::GoldenPath;
using testing::ReadGoldenCsv;
using testing::ReadJsonFile;

// ---- golden vectors (antropy) ----------------------------------------------------------------

TEST(SampleEntropy, MatchesAntropyGoldenValues) {
  const auto meta = ReadJsonFile(GoldenPath("sample_entropy/sample_entropy.json"));
  const auto signals = ReadGoldenCsv(GoldenPath("sample_entropy/signals.csv"));
  int checked = 0;
  for (const auto& c : meta.at("cases")) {
    const std::string name = c.at("signal").get<std::string>();
    SCOPED_TRACE(name + " m=" + std::to_string(c.at("m").get<int>()) + " r_factor=" +
                 std::to_string(c.at("r_factor").get<double>()));
    const auto& x = signals.at(name);
    SampleEntropyOptions opt;
    opt.m = c.at("m").get<int>();
    opt.r_factor = c.at("r_factor").get<double>();
    for (auto algo : {SampleEntropyAlgorithm::kFast, SampleEntropyAlgorithm::kBruteForce}) {
      opt.algorithm = algo;
      auto r = SampleEntropy(x, opt);
      ASSERT_TRUE(r.ok()) << r.error().message;
      // r: the population SD times the factor; only summation order differs from numpy.
      EXPECT_NEAR(r->r, c.at("r").get<double>(), 1e-14 * c.at("r").get<double>());
      // 1e-12: SampEn is -ln of a ratio of integer counts, so equal counts give the
      // same value up to the last bit of log(); any miscounted pair moves it by > 1e-7 here.
      EXPECT_NEAR(r->sample_entropy, c.at("sample_entropy").get<double>(), 1e-12);
    }
    ++checked;
  }
  EXPECT_EQ(checked, 45);
}

// ---- closed-form cases -----------------------------------------------------------------------

TEST(SampleEntropy, HandCountedAlternatingSeries) {
  // x = 1 2 1 2 1 2, m = 1, r = 0.5: 5 templates (N - m) of each length.
  // Length 1: values 1 2 1 2 1 -> pairs of equal values: C(3,2) + C(2,2) = 4 = B.
  // Length 2: (1,2) (2,1) (1,2) (2,1) (1,2) -> C(3,2) + C(2,2) = 4 = A. SampEn = 0.
  const std::vector<double> x = {1, 2, 1, 2, 1, 2};
  SampleEntropyOptions opt;
  opt.m = 1;
  opt.r_absolute = 0.5;
  auto r = SampleEntropy(x, opt);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->b_matches, 4u);
  EXPECT_EQ(r->a_matches, 4u);
  EXPECT_EQ(r->sample_entropy, 0.0);
}

TEST(SampleEntropy, DistanceEqualToRIsNotAMatch) {
  // Steps of exactly 1 (exact in binary): |1 - 0| = 1 is not < r = 1 (strict).
  const std::vector<double> x = {0, 1, 0, 1, 0, 1, 0};
  SampleEntropyOptions opt;
  opt.m = 1;
  opt.r_absolute = 1.0;
  auto r = SampleEntropy(x, opt);
  ASSERT_TRUE(r.ok());
  // Length 1 over 6 templates 0 1 0 1 0 1: only equal values match: 3 + 3 = 6 pairs.
  EXPECT_EQ(r->b_matches, 6u);
  EXPECT_EQ(r->a_matches, 6u);
  opt.r_absolute = std::nextafter(1.0, 2.0);  // now every pair matches
  auto r2 = SampleEntropy(x, opt);
  ASSERT_TRUE(r2.ok());
  EXPECT_EQ(r2->b_matches, 15u);  // C(6, 2)
  EXPECT_EQ(r2->a_matches, 15u);
}

TEST(SampleEntropy, NoLongerMatchGivesInfinityAndNoMatchIsUndefined) {
  const std::vector<double> x = {0, 10, 0, 20, 0, 30, 0, 40};
  SampleEntropyOptions opt;
  opt.m = 1;
  opt.r_absolute = 0.5;
  auto r = SampleEntropy(x, opt);  // the zeros match at length 1, never at length 2
  ASSERT_TRUE(r.ok());
  EXPECT_GT(r->b_matches, 0u);
  EXPECT_EQ(r->a_matches, 0u);
  EXPECT_TRUE(std::isinf(r->sample_entropy));
  EXPECT_TRUE(r->defined);
  const std::vector<double> y = {0, 1, 2, 3, 4, 5};
  auto u = SampleEntropy(y, opt);
  ASSERT_TRUE(u.ok());
  EXPECT_FALSE(u->defined);
  EXPECT_TRUE(std::isnan(u->sample_entropy));
}

TEST(SampleEntropy, WhiteNoiseScoresAboutTwoPointTwo) {
  // Gaussian white noise, m = 2, r = 0.2 SD: SampEn -> -ln P(|d| < r) with d ~ N(0, 2 sigma^2),
  // P = erf(0.2 / 2) = 0.1125 -> 2.185. With N = 20000 the estimate's spread is ~0.02.
  std::mt19937 rng(1);
  std::normal_distribution<double> g(0, 1);
  std::vector<double> x(20000);
  for (double& v : x) v = g(rng);
  auto r = SampleEntropy(x);
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(r->sample_entropy, -std::log(std::erf(0.1)), 0.06);
}

TEST(SampleEntropy, ReferenceSdAndAbsoluteTolerance) {
  std::vector<double> x(500);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.1 * i);
  SampleEntropyOptions opt;
  opt.reference_sd = 2.0;
  auto a = SampleEntropy(x, opt);
  ASSERT_TRUE(a.ok());
  EXPECT_DOUBLE_EQ(a->r, 0.4);
  opt.r_absolute = 0.4;
  opt.reference_sd.reset();
  auto b = SampleEntropy(x, opt);
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(a->sample_entropy, b->sample_entropy);
}

TEST(SampleEntropy, RejectsBadInput) {
  SampleEntropyOptions opt;
  opt.m = 0;
  std::string why;
  EXPECT_FALSE(opt.IsValid(&why));
  EXPECT_EQ(why, "SampleEntropyOptions::m = 0: must be in 1..10");
  EXPECT_EQ(SampleEntropy(std::vector<double>(100, 1.0), opt).error().kind, ErrorKind::kInvalidArgument);
  auto constant = SampleEntropy(std::vector<double>(100, 3.0));
  ASSERT_FALSE(constant.ok());
  EXPECT_EQ(constant.error().kind, ErrorKind::kInvalidInput);
  EXPECT_FALSE(SampleEntropy(std::vector<double>{1, 2, 3}).ok());  // N < m + 2
  std::vector<double> bad(50, 1.0);
  bad[3] = INFINITY;
  EXPECT_FALSE(SampleEntropy(bad).ok());
}

// ---- fast == brute force ---------------------------------------------------------------------

struct Case {
  const char* name;
  std::vector<double> x;
};

std::vector<Case> Inputs(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Case> cases;
  Case white{"white", {}}, quant{"quantized", {}}, smooth{"smooth", {}}, walk{"walk_quantized", {}},
      few{"few_levels", {}}, uni{"uniform", {}};
  double w = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double v = g(rng);
    white.x.push_back(v);
    // ADIS16405-like: 0.05 deg/s steps, so distances equal to r (multiples of 0.05) occur.
    quant.x.push_back(std::round(v * 0.1 / 0.05) * 0.05);
    smooth.x.push_back(std::sin(2 * std::numbers::pi * 0.004 * i) + 0.01 * v);
    w += v;
    walk.x.push_back(std::round(w / 2) * 0.05);
    few.x.push_back(static_cast<double>(static_cast<int>(rng() % 3)));
    uni.x.push_back(u(rng));
  }
  cases = {white, quant, smooth, walk, few, uni};
  return cases;
}

// ---- extreme but finite values -------------------------------------------------------------

TEST(SampleEntropy, ExtremeScalesGiveTheCountsOfTheUnscaledSeries) {
  // A golden series scaled by 2^e: the counts must be those of the series itself (a power of two
  // commutes with every difference and comparison) and r scales by 2^e. Unnormalised, at 2^1000
  // (~1e301) the SD's squares overflow, and at 2^-1000 (~1e-301) they underflow to an SD of 0.
  const auto signals = ReadGoldenCsv(GoldenPath("sample_entropy/signals.csv"));
  for (const auto& [name, x] : signals) {
    SCOPED_TRACE(name);
    auto ref = SampleEntropy(x, SampleEntropyOptions{});
    ASSERT_TRUE(ref.ok());
    for (int e : {1000, -1000, 300}) {
      SCOPED_TRACE("scale 2^" + std::to_string(e));
      std::vector<double> y(x.size());
      for (std::size_t i = 0; i < x.size(); ++i) y[i] = std::ldexp(x[i], e);
      for (auto algo : {SampleEntropyAlgorithm::kFast, SampleEntropyAlgorithm::kBruteForce}) {
        SampleEntropyOptions opt;
        opt.algorithm = algo;
        auto r = SampleEntropy(y, opt);
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_EQ(r->a_matches, ref->a_matches);
        EXPECT_EQ(r->b_matches, ref->b_matches);
        EXPECT_EQ(r->r, std::ldexp(ref->r, e));
        EXPECT_EQ(r->sample_entropy, ref->sample_entropy);
      }
      SampleEntropyOptions opt;  // a tolerance given in the series' unit scales with it too
      opt.r_absolute = std::ldexp(ref->r, e);
      auto r = SampleEntropy(y, opt);
      ASSERT_TRUE(r.ok()) << r.error().message;
      EXPECT_EQ(r->sample_entropy, ref->sample_entropy);
    }
  }
}

TEST(SampleEntropy, AlternatingPlusMinus1e308IsCountedExactly) {
  // x_i = +-1e308 alternating with period 3 (+, -, -): differences of 2e308 overflow unless
  // normalised. Templates of length 2 match exactly when they start at the same phase: N - m = 298
  // templates in phases of sizes 100, 99, 99; the same for length 3.
  std::vector<double> x(300);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = (i % 3 == 0) ? 1e308 : -1e308;
  for (auto algo : {SampleEntropyAlgorithm::kFast, SampleEntropyAlgorithm::kBruteForce}) {
    SampleEntropyOptions opt;
    opt.algorithm = algo;
    auto r = SampleEntropy(x, opt);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const std::uint64_t pairs = 100 * 99 / 2 + 2 * (99 * 98 / 2);
    EXPECT_EQ(r->b_matches, pairs);
    EXPECT_EQ(r->a_matches, pairs);
    EXPECT_EQ(r->sample_entropy, 0.0);
    EXPECT_TRUE(std::isfinite(r->r));
  }
}

TEST(SampleEntropy, FastCountsEqualBruteForce) {
  for (unsigned seed : {1u, 2u}) {
    for (std::size_t n : {30u, 257u, 1000u}) {
      for (const Case& c : Inputs(n, seed)) {
        const double sd = PopulationSd(c.x);
        // Relative tolerances, and absolute ones that are exact multiples of the quantization
        // step (ties at distance == r).
        std::vector<double> rs = {0.1 * sd, 0.2 * sd, 0.5 * sd, 0.05, 0.1, 1.0};
        for (int m : {1, 2, 3}) {
          for (double r : rs) {
            if (!(r > 0)) continue;
            const auto fast = CountTemplateMatches(c.x, m, r, SampleEntropyAlgorithm::kFast);
            const auto brute = CountTemplateMatches(c.x, m, r, SampleEntropyAlgorithm::kBruteForce);
            EXPECT_EQ(fast.a, brute.a) << c.name << " n=" << n << " m=" << m << " r=" << r;
            EXPECT_EQ(fast.b, brute.b) << c.name << " n=" << n << " m=" << m << " r=" << r;
          }
        }
      }
    }
  }
}

TEST(SampleEntropy, FastEqualsBruteForceOnLongSmoothAndQuantizedSeries) {
  // Nearly every pair matches here: the case that makes pair-walking methods O(N^2).
  // Above 2048 items the window counts use a Fenwick tree and above 512 the sorts a radix sort;
  // the white-noise series (few matches) sends many mid-sized sets through both.
  const std::size_t n = 6000;
  std::vector<double> slow(n), steps(n), noise(n);
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0, 0.02);
  for (std::size_t i = 0; i < n; ++i) {
    slow[i] = std::sin(2 * std::numbers::pi * i / 3000.0) + 0.3 * std::sin(2 * std::numbers::pi * i / 211.0);
    steps[i] = std::round((slow[i] + g(rng)) / 0.05) * 0.05;
    noise[i] = 0.1 * std::sin(2 * std::numbers::pi * i / 5000.0) + g(rng);
  }
  for (const auto* x : {&slow, &steps, &noise}) {
    for (int m : {2, 3}) {
      for (double r : {0.2 * PopulationSd(*x), 0.15}) {
        const auto fast = CountTemplateMatches(*x, m, r, SampleEntropyAlgorithm::kFast);
        const auto brute = CountTemplateMatches(*x, m, r, SampleEntropyAlgorithm::kBruteForce);
        EXPECT_EQ(fast.a, brute.a) << "m=" << m << " r=" << r;
        EXPECT_EQ(fast.b, brute.b) << "m=" << m << " r=" << r;
      }
    }
  }
}

TEST(SampleEntropy, HigherEmbeddingDimensionsAgreeToo) {
  // m = 4 and 5 exercise the recursion beyond the Fenwick base case.
  for (const Case& c : Inputs(400, 9)) {
    for (int m : {4, 5}) {
      const double r = 0.5 * PopulationSd(c.x);
      const auto fast = CountTemplateMatches(c.x, m, r, SampleEntropyAlgorithm::kFast);
      const auto brute = CountTemplateMatches(c.x, m, r, SampleEntropyAlgorithm::kBruteForce);
      EXPECT_EQ(fast.a, brute.a) << c.name << " m=" << m;
      EXPECT_EQ(fast.b, brute.b) << c.name << " m=" << m;
    }
  }
}

}  // namespace
}  // namespace gyrocomp

namespace gyrocomp {
namespace {

TEST(SampleEntropy, ThreadCountDoesNotChangeCounts) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0, 1);
  std::vector<double> x(30000);
  double phase = 0;
  for (double& v : x) {
    phase += 0.05 + 0.02 * g(rng);
    v = std::round(std::cos(phase) / 0.05) * 0.05;
  }
  for (int m : {1, 2, 3}) {
    const double r = 0.2 * PopulationSd(x);
    const auto one = CountTemplateMatches(x, m, r, SampleEntropyAlgorithm::kFast, 1);
    const auto three = CountTemplateMatches(x, m, r, SampleEntropyAlgorithm::kFast, 3);
    EXPECT_EQ(one.a, three.a) << m;
    EXPECT_EQ(one.b, three.b) << m;
    EXPECT_GT(one.a, 0u);
  }
}

}  // namespace
}  // namespace gyrocomp

// ---- cancellation ----------------------------------------------------------------------------

#include <chrono>
#include <cstdio>
#include <thread>

#include "gyrocomp/decompose/feature_classifier.h"

namespace gyrocomp {
namespace {

std::vector<double> WhiteNoise(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, 1);
  std::vector<double> x(n);
  for (double& v : x) v = g(rng);
  return x;
}

// Runs SampleEntropy with a token that another thread sets 50 ms in; true when it threw Cancelled.
// The series and options are chosen so that the count takes many seconds: a result means the
// counter did not poll the token. The latency is printed, not asserted.
bool CancelledWhileCounting(const std::vector<double>& x, SampleEntropyOptions opt, const char* what) {
  CancellationToken token;
  opt.cancel = &token;
  return testing::CancelledWhileRunning(token, [&] { (void)SampleEntropy(x, opt); }, what);
}

TEST(SampleEntropyCancel, ATokenSetBeforeTheCallThrowsCancelled) {
  const std::vector<double> x = WhiteNoise(2000, 1);
  CancellationToken token;
  token.Cancel();
  for (auto algo : {SampleEntropyAlgorithm::kFast, SampleEntropyAlgorithm::kRangeCount,
                    SampleEntropyAlgorithm::kSortedWindow, SampleEntropyAlgorithm::kBruteForce}) {
    SampleEntropyOptions opt;
    opt.algorithm = algo;
    opt.cancel = &token;
    EXPECT_THROW((void)SampleEntropy(x, opt), Cancelled) << static_cast<int>(algo);
    EXPECT_THROW((void)CountTemplateMatches(x, 2, 0.2, algo, 2, &token), Cancelled) << static_cast<int>(algo);
  }
}

TEST(SampleEntropyCancel, AnUnsetTokenChangesNoCount) {
  // Long enough for several cancellation chunks in every counter (2^16 templates or 2^22 pairs:
  // 2.3 template chunks here, and ~10^9 candidate pairs in the sorted window).
  const std::vector<double> x = WhiteNoise(150000, 2);
  const CancellationToken token;
  for (auto algo : {SampleEntropyAlgorithm::kRangeCount, SampleEntropyAlgorithm::kSortedWindow}) {
    for (int threads : {1, 2}) {
      const double r = 0.2 * PopulationSd(x);
      const auto plain = CountTemplateMatches(x, 2, r, algo, threads);
      const auto polled = CountTemplateMatches(x, 2, r, algo, threads, &token);
      EXPECT_EQ(plain.a, polled.a);
      EXPECT_EQ(plain.b, polled.b);
      EXPECT_GT(plain.a, 0u);
    }
  }
}

TEST(SampleEntropyCancel, EveryCounterStopsWhenTheTokenIsSetDuringTheCount) {
  // The sorted window with r spanning every value: all N^2 / 2 pairs are candidates (10^11 here,
  // minutes); range counting with m = 10 on 4 M samples of noise (seconds); the brute force on
  // 10^5 samples (5 x 10^9 pairs, seconds). The token is set 50 ms after the call starts.
  const std::vector<double> big = WhiteNoise(4000000, 3);
  SampleEntropyOptions window;
  window.algorithm = SampleEntropyAlgorithm::kSortedWindow;
  window.r_absolute = 100.0;
  window.num_threads = 2;
  const std::vector<double> half(big.begin(), big.begin() + 500000);
  EXPECT_TRUE(CancelledWhileCounting(half, window, "sorted window, N = 5e5, r > span"));
  SampleEntropyOptions range;
  range.algorithm = SampleEntropyAlgorithm::kRangeCount;
  range.m = 10;
  for (int threads : {1, 2}) {
    range.num_threads = threads;
    EXPECT_TRUE(CancelledWhileCounting(big, range, "range counting, N = 4e6, m = 10"));
  }
  SampleEntropyOptions brute;
  brute.algorithm = SampleEntropyAlgorithm::kBruteForce;
  const std::vector<double> small(big.begin(), big.begin() + 100000);
  EXPECT_TRUE(CancelledWhileCounting(small, brute, "brute force, N = 1e5"));
}

TEST(SampleEntropyCancel, TheClassifierThrowsCancelledFromItsWorkerThreads) {
  VmdResult vmd;
  for (int k = 0; k < 4; ++k) {
    vmd.modes.push_back(WhiteNoise(5000, 10 + k));
    vmd.summary.center_frequency_hz.push_back(k + 1.0);
    vmd.summary.center_frequency_cycles_per_sample.push_back((k + 1.0) / 100.0);
  }
  CancellationToken token;
  token.Cancel();
  SampleEntropyOptions se;
  se.cancel = &token;
  se.num_threads = 2;  // two modes at a time: the Cancelled of a worker thread must not terminate
  EXPECT_THROW((void)ClassifyVmdModes(vmd, se), Cancelled);
}

}  // namespace
}  // namespace gyrocomp
