#include "gyrocomp/decompose/vmd.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "test_support.h"
#include "vmd_kernel.h"

namespace gyrocomp {
namespace {

using testing::GoldenPath;
using testing::ReadGoldenCsv;
using testing::ReadJsonFile;

double Rms(const std::vector<double>& x) {
  double s = 0;
  for (double v : x) s += v * v;
  return std::sqrt(s / x.size());
}

std::vector<double> Tone(std::size_t n, double cycles_per_sample, double amplitude, double phase = 0) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = amplitude * std::cos(2 * std::numbers::pi * cycles_per_sample * i + phase);
  }
  return x;
}

// ---- golden vectors (vmdpy) ---------------------------------------------------------------

// The options of a golden run: its "params" (K, alpha, tau, tol, DC, max_iterations).
VmdOptions GoldenOptions(const nlohmann::json& p) {
  VmdOptions opt;
  opt.num_modes = p.at("K").get<int>();
  opt.alpha = p.at("alpha").get<double>();
  opt.tau = p.at("tau").get<double>();
  opt.tol = p.at("tol").get<double>();
  opt.dc = p.at("DC").get<int>() != 0;
  opt.max_iterations = p.at("max_iterations").get<int>();
  return opt;
}

class VmdGolden : public ::testing::TestWithParam<const char*> {};

TEST_P(VmdGolden, MatchesVmdpy) {
  const std::string name = GetParam();
  const auto meta = ReadJsonFile(GoldenPath("vmd/" + name + ".json"));
  const auto input = ReadGoldenCsv(GoldenPath("vmd/" + name + ".input.csv")).at("x");
  const auto modes = ReadGoldenCsv(GoldenPath("vmd/" + name + ".modes.csv"));
  const auto& p = meta.at("params");

  VmdOptions opt = GoldenOptions(p);
  ASSERT_EQ(p.at("init").get<int>(), 1);
  opt.init = VmdInit::kUniform;
  for (int threads : {1, 2}) {
    SCOPED_TRACE("threads = " + std::to_string(threads));
    opt.num_threads = threads;
    auto r = DecomposeVmd(input, opt);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const VmdSummary& s = r->summary;
    EXPECT_EQ(s.iterations, meta.at("iterations").get<int>());
    EXPECT_TRUE(s.converged);
    const auto golden_w = meta.at("final_center_frequency_cycles_per_sample").get<std::vector<double>>();
    ASSERT_EQ(s.center_frequency_cycles_per_sample.size(), golden_w.size());
    for (std::size_t k = 0; k < golden_w.size(); ++k) {
      // 1e-12 cycles/sample (observed <= 8e-15): FFT (pocketfft vs FFTW) and summation-order rounding is ~1e-16
      // relative per step; the iteration is contractive, so differences stay near that level.
      // 1e-12 leaves room for that while catching any algorithmic difference (a one-iteration
      // shift moves these by > 1e-9).
      EXPECT_NEAR(s.center_frequency_cycles_per_sample[k], golden_w[k], 1e-12) << "mode " << k + 1;
    }
    // Every mode within 1e-8 x input RMS (the acceptance bound). Observed: <= 4.4e-14 x RMS
    // (gyro_like_K6), i.e. rounding only.
    const double tol = 1e-8 * Rms(input);
    ASSERT_EQ(r->modes.size(), static_cast<std::size_t>(opt.num_modes));
    for (int k = 0; k < opt.num_modes; ++k) {
      const auto& g = modes.at("mode_" + std::to_string(k + 1));
      ASSERT_EQ(r->modes[k].size(), g.size());
      double worst = 0;
      for (std::size_t i = 0; i < g.size(); ++i) worst = std::max(worst, std::abs(r->modes[k][i] - g[i]));
      EXPECT_LE(worst, tol) << "mode " << k + 1;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllCases, VmdGolden,
                         ::testing::Values("three_tones_K3", "tones_dc_K4", "tones_tau_K3", "gyro_like_K6"));

// ---- closed-form cases ---------------------------------------------------------------------

TEST(Vmd, PureTonesLandInSeparateModesAtTheirFrequencies) {
  const std::size_t n = 2000;
  const double f1 = 0.01, f2 = 0.1, f3 = 0.3;  // cycles per sample
  std::vector<double> x(n);
  const auto a = Tone(n, f1, 1.0), b = Tone(n, f2, 0.7, 0.3), c = Tone(n, f3, 0.4, 1.1);
  for (std::size_t i = 0; i < n; ++i) x[i] = a[i] + b[i] + c[i];
  VmdOptions opt;
  opt.num_modes = 3;
  opt.fs_hz = 100.0;
  auto r = DecomposeVmd(x, opt);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto& w = r->summary.center_frequency_cycles_per_sample;
  // Centre frequencies: the grid of the extended signal is 1/T = 1/4000 cycles per sample; a
  // pure tone's power-weighted mean lands within a small fraction of a bin of it.
  EXPECT_NEAR(w[0], f1, 2e-4);
  EXPECT_NEAR(w[1], f2, 2e-4);
  EXPECT_NEAR(w[2], f3, 2e-4);
  EXPECT_NEAR(r->summary.center_frequency_hz[1], f2 * 100.0, 2e-2);
  // Each mode reproduces its tone away from the ends (the mirror extension is not periodic).
  const std::vector<const std::vector<double>*> tones = {&a, &b, &c};
  for (int k = 0; k < 3; ++k) {
    double err = 0, ref = 0;
    for (std::size_t i = n / 10; i < n - n / 10; ++i) {
      err += std::pow(r->modes[k][i] - (*tones[k])[i], 2);
      ref += std::pow((*tones[k])[i], 2);
    }
    // A tone alone in its mode: residual energy below 1% of the tone's (the Wiener filters of
    // the neighbours leak a little of each tone: alpha = 2000 bandwidth vs 0.09 spacing).
    EXPECT_LT(err / ref, 1e-2) << "mode " << k + 1;
  }
}

TEST(Vmd, DcOptionKeepsModeOneAtZero) {
  const std::size_t n = 1000;
  auto x = Tone(n, 0.05, 1.0);
  for (double& v : x) v += 2.5;  // DC offset
  VmdOptions opt;
  opt.num_modes = 2;
  opt.dc = true;
  auto r = DecomposeVmd(x, opt);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->summary.center_frequency_cycles_per_sample[0], 0.0);
  EXPECT_NEAR(r->summary.center_frequency_cycles_per_sample[1], 0.05, 2e-4);
  double mean0 = 0;
  for (double v : r->modes[0]) mean0 += v / n;
  EXPECT_NEAR(mean0, 2.5, 0.05);  // the DC mode carries the offset
}

TEST(Vmd, ThreadCountDoesNotChangeResults) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0, 1);
  std::vector<double> x(40000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = g(rng) + std::sin(0.001 * i);
  // K = 6: the bin-major kernel; K = 9 (> vmd_internal::kMaxModesAtOnce): the mode-major one.
  for (int K : {6, 9}) {
    SCOPED_TRACE("K = " + std::to_string(K));
    VmdOptions opt;
    opt.num_modes = K;
    opt.max_iterations = 20;
    opt.num_threads = 1;
    auto a = DecomposeVmd(x, opt);
    opt.num_threads = 2;
    auto b = DecomposeVmd(x, opt);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->summary.iterations, b->summary.iterations);
    EXPECT_EQ(a->modes, b->modes);  // bit-identical: fixed reduction blocks
    EXPECT_EQ(a->summary.center_frequency_cycles_per_sample, b->summary.center_frequency_cycles_per_sample);
    EXPECT_FALSE(a->summary.converged);  // 19 updates are not enough for noise
    EXPECT_EQ(a->summary.iterations, 19);  // max_iterations - 1 updates (reference Niter)
  }
}

// Updates run in place except those predicted to precede the last one (vmd.cc: KeepPrevious);
// when the prediction misses, the run is repeated keeping from that update on. Horizon 0 never
// predicts, so every converged run is repeated: it must give exactly the bits of the default run,
// report each update to on_iteration once, and the golden iteration count; with tau > 0 too.
TEST(Vmd, InPlaceUpdatesAndTheirRerunGiveTheSameBits) {
  for (const char* name : {"three_tones_K3", "tones_tau_K3", "gyro_like_K6"}) {
    SCOPED_TRACE(name);
    const auto meta = ReadJsonFile(GoldenPath(std::string("vmd/") + name + ".json"));
    const auto input = ReadGoldenCsv(GoldenPath(std::string("vmd/") + name + ".input.csv")).at("x");
    VmdOptions opt = GoldenOptions(meta.at("params"));  // DC = 0 in these three
    std::vector<int> reported;
    opt.on_iteration = [&](int n, double) { reported.push_back(n); };
    int reruns = 0;
    auto a = DecomposeVmd(input, opt);
    const std::vector<int> reported_default = reported;
    reported.clear();
    vmd_internal::VmdTuning never_predict;
    never_predict.lookahead_steps = 0;
    auto b = vmd_internal::DecomposeVmdTuned(input, opt, never_predict, &reruns);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(reruns, 1);
    EXPECT_EQ(b->summary.iterations, meta.at("iterations").get<int>());
    EXPECT_EQ(a->summary.iterations, b->summary.iterations);
    EXPECT_EQ(a->modes, b->modes);  // bit-identical
    EXPECT_EQ(a->summary.center_frequency_cycles_per_sample, b->summary.center_frequency_cycles_per_sample);
    EXPECT_EQ(a->summary.final_update, b->summary.final_update);
    ASSERT_EQ(reported.size(), static_cast<std::size_t>(b->summary.iterations));
    for (std::size_t i = 0; i < reported.size(); ++i) EXPECT_EQ(reported[i], static_cast<int>(i) + 1);
    EXPECT_EQ(reported, reported_default);
    // The last iterate needs no predecessor: fully in place, never repeated.
    opt.return_last_iterate = true;
    reruns = 0;
    auto c = vmd_internal::DecomposeVmdTuned(input, opt, never_predict, &reruns);
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(reruns, 0);
    EXPECT_EQ(c->summary.iterations, a->summary.iterations);
  }
}

// Centre-frequency extrapolation (VmdOptions::omega_extrapolation_period): the same fixed point as
// the reference iteration, reached in fewer updates. Gyro-like record of vmd_benchmark (noise
// 0.05, slow sine, ramp), 20,000 samples, the option forced on (min_samples 0). The limit is
// approximated by the reference iteration run to tol 1e-13 (675 updates). At tol 1e-10 and 1e-7,
// the extrapolated run must stop in fewer than half the reference's updates and no farther from
// that limit than the reference run at the same tol (measured: 113 vs 517 updates, 4.4e-5 vs
// 5.1e-5 x RMS at 1e-10; 80 vs 359, 1.30e-3 vs 1.64e-3 at 1e-7); 1.25x is the margin for
// rounding-level differences between machines, far below the 10-20x a wrong fixed point gives.
double MaxModeDistance(const VmdResult& a, const VmdResult& b) {
  double worst = 0;
  for (std::size_t k = 0; k < a.modes.size(); ++k) {
    for (std::size_t i = 0; i < a.modes[k].size(); ++i) worst = std::max(worst, std::abs(a.modes[k][i] - b.modes[k][i]));
  }
  return worst;
}

TEST(Vmd, CenterFrequencyExtrapolationReachesTheSameDecompositionInFewerUpdates) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0, 0.05);
  const std::size_t n = 20000;
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = 0.2 * std::sin(2 * std::numbers::pi * i / (0.7 * n)) + 0.01 * i / n + g(rng);
  VmdOptions plain;
  plain.omega_extrapolation_period.reset();
  plain.max_iterations = 20000;
  VmdOptions limit = plain;
  limit.tol = 1e-13;
  auto ref = DecomposeVmd(x, limit);
  ASSERT_TRUE(ref.ok() && ref->summary.converged);
  for (double tol : {1e-10, 1e-7}) {
    SCOPED_TRACE("tol = " + std::to_string(tol));
    plain.tol = tol;
    VmdOptions fast = plain;
    fast.omega_extrapolation_period = 5;
    fast.omega_extrapolation_min_samples = 0;
    auto a = DecomposeVmd(x, plain);
    auto b = DecomposeVmd(x, fast);
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_TRUE(a->summary.converged && b->summary.converged);
    EXPECT_FALSE(a->summary.omega_extrapolation_period.has_value());
    EXPECT_EQ(b->summary.omega_extrapolation_period, 5);
    EXPECT_LT(2 * b->summary.iterations, a->summary.iterations);
    const double err_plain = MaxModeDistance(*a, *ref), err_fast = MaxModeDistance(*b, *ref);
    EXPECT_LE(err_fast, 1.25 * err_plain) << err_fast / Rms(x) << " vs " << err_plain / Rms(x) << " x RMS";
  }
}

// Below omega_extrapolation_min_samples the defaults are the reference iteration, bit for bit.
TEST(Vmd, ShortRecordsFollowTheReferenceIterationByDefault) {
  std::mt19937 rng(9);
  std::normal_distribution<double> g(0, 1);
  std::vector<double> x(5000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = g(rng) + std::sin(0.002 * i);
  VmdOptions def;
  VmdOptions off;
  off.omega_extrapolation_period.reset();
  ASSERT_LT(x.size(), def.omega_extrapolation_min_samples);
  auto a = DecomposeVmd(x, def);
  auto b = DecomposeVmd(x, off);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_FALSE(a->summary.omega_extrapolation_period.has_value());
  EXPECT_EQ(a->summary.iterations, b->summary.iterations);
  EXPECT_EQ(a->modes, b->modes);
  VmdOptions bad;
  bad.omega_extrapolation_period = 2;
  std::string why;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("omega_extrapolation_period"), std::string::npos) << why;
}

// ---- extreme but finite inputs -------------------------------------------------------------
// DecomposeVmd normalises the signal by a power of two, which commutes exactly with every
// floating-point operation of the algorithm; the absolute tolerance (squared signal units) is
// scaled by the square of that power. So a signal scaled by 2^e with tol scaled by 2^(2e) must
// give the same iteration count and exactly the scaled modes and the same centre frequencies.

TEST(VmdExtremeValues, ScaledGoldenInputGivesExactlyScaledModesAndTheGoldenIterationCount) {
  const auto meta = ReadJsonFile(GoldenPath("vmd/gyro_like_K6.json"));
  const auto input = ReadGoldenCsv(GoldenPath("vmd/gyro_like_K6.input.csv")).at("x");
  const VmdOptions base = GoldenOptions(meta.at("params"));
  auto ref = DecomposeVmd(input, base);
  ASSERT_TRUE(ref.ok());
  ASSERT_EQ(ref->summary.iterations, meta.at("iterations").get<int>());
  // 2^400 ~ 2.6e120 and 2^-400 ~ 3.9e-121: tol * 2^(+-800) stays a normal double.
  for (int e : {400, -400}) {
    SCOPED_TRACE("scale 2^" + std::to_string(e));
    std::vector<double> x(input.size());
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::ldexp(input[i], e);
    VmdOptions opt = base;
    opt.tol = std::ldexp(base.tol, 2 * e);
    auto r = DecomposeVmd(x, opt);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->summary.iterations, meta.at("iterations").get<int>());
    EXPECT_TRUE(r->summary.converged);
    EXPECT_EQ(r->summary.center_frequency_cycles_per_sample, ref->summary.center_frequency_cycles_per_sample);
    EXPECT_EQ(r->summary.final_update, std::ldexp(ref->summary.final_update, 2 * e));
    for (int k = 0; k < opt.num_modes; ++k) {
      for (std::size_t i = 0; i < x.size(); ++i) {
        ASSERT_EQ(r->modes[k][i], std::ldexp(ref->modes[k][i], e)) << "mode " << k + 1 << " sample " << i;
      }
    }
  }
}

TEST(VmdExtremeValues, NearTheEdgesOfTheDoubleRangeTheRelativeRuleIsScaleFree) {
  const auto input = ReadGoldenCsv(GoldenPath("vmd/gyro_like_K6.input.csv")).at("x");
  VmdOptions opt;
  opt.stopping_rule = VmdStoppingRule::kRelative;
  opt.tol = 1e-6;
  auto ref = DecomposeVmd(input, opt);
  ASSERT_TRUE(ref.ok());
  // Peaks of the input ~0.3: 2^1000 x ~ 3e300, 2^-1000 x ~ 3e-302 (both still normal).
  for (int e : {1000, -1000}) {
    SCOPED_TRACE("scale 2^" + std::to_string(e));
    std::vector<double> x(input.size());
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::ldexp(input[i], e);
    auto r = DecomposeVmd(x, opt);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->summary.iterations, ref->summary.iterations);
    EXPECT_EQ(r->summary.final_update, ref->summary.final_update);
    for (int k = 0; k < opt.num_modes; ++k) {
      for (std::size_t i = 0; i < x.size(); ++i) {
        ASSERT_EQ(r->modes[k][i], std::ldexp(ref->modes[k][i], e)) << "mode " << k + 1 << " sample " << i;
      }
    }
  }
}

// A record scaled to ~3e-302 under the default absolute rule. Normalised, tol = 1e-7
// squared signal units becomes +inf; the loop ran no update and the reconstruction read a null
// iterate (SIGSEGV). Now the first update always runs; the rule is then met at once and the
// reference would return its all-zero initial modes, which is refused with the reason.
TEST(VmdExtremeValues, AbsoluteToleranceAboveTheSignalPowerIsRefusedNotACrash) {
  const auto input = ReadGoldenCsv(GoldenPath("vmd/gyro_like_K6.input.csv")).at("x");
  for (int e : {-1000, -1060, -660}) {  // ~3e-302, a subnormal-range input, ~1e-200
    SCOPED_TRACE("scale 2^" + std::to_string(e));
    std::vector<double> x(input.size());
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::ldexp(input[i], e);
    VmdOptions opt;  // absolute rule, tol 1e-7
    auto r = DecomposeVmd(x, opt);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().kind, ErrorKind::kInvalidInput);
    EXPECT_NE(r.error().message.find("--vmd-stop relative"), std::string::npos) << r.error().message;
    opt.return_last_iterate = true;  // the one update's iterate is a (finite) answer
    auto last = DecomposeVmd(x, opt);
    ASSERT_TRUE(last.ok()) << last.error().message;
    EXPECT_EQ(last->summary.iterations, 1);
    for (const auto& mode : last->modes) {
      for (double v : mode) ASSERT_TRUE(std::isfinite(v));
    }
  }
}

TEST(VmdExtremeValues, AlternatingPlusMinus1e308GivesFiniteModesExactlyScaledFromASmallCopy) {
  // A square wave of amplitude 1e308: unnormalised, its spectrum and squared sums overflow (the
  // modes came out NaN). Normalised, the modes are finite and exactly 2^1023 times those of the
  // same wave scaled down by 2^1023 (same relative rule, same number of updates).
  std::vector<double> x(512), small(512);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = (i % 3 ? -1e308 : 1e308);
    small[i] = std::ldexp(x[i], -1023);
  }
  VmdOptions opt;
  opt.num_modes = 3;
  opt.max_iterations = 50;
  // Default (absolute) rule: 1e-7 squared signal units cannot be met by such a signal (vmdpy on
  // it would not stop either), but every number is finite.
  auto a = DecomposeVmd(x, opt);
  ASSERT_TRUE(a.ok()) << a.error().message;
  EXPECT_FALSE(a->summary.converged);
  EXPECT_TRUE(std::isfinite(a->summary.final_update));  // saturates at the largest double
  for (const auto& mode : a->modes) {
    for (double v : mode) ASSERT_TRUE(std::isfinite(v));
  }
  opt.stopping_rule = VmdStoppingRule::kRelative;
  auto big = DecomposeVmd(x, opt);
  auto ref = DecomposeVmd(small, opt);
  ASSERT_TRUE(big.ok() && ref.ok());
  EXPECT_EQ(big->summary.iterations, ref->summary.iterations);
  for (int k = 0; k < opt.num_modes; ++k) {
    for (std::size_t i = 0; i < x.size(); ++i) {
      ASSERT_EQ(big->modes[k][i], std::ldexp(ref->modes[k][i], 1023)) << "mode " << k + 1 << " sample " << i;
    }
  }
  EXPECT_EQ(big->summary.center_frequency_cycles_per_sample, ref->summary.center_frequency_cycles_per_sample);
}

TEST(Vmd, WarmStartFromCenterFrequencies) {
  // Started at the centre frequencies a full run ends at, the same tolerance is met in fewer
  // updates, and the modes are those of the full run within the accuracy the rule allows.
  const auto input = ReadGoldenCsv(GoldenPath("vmd/gyro_like_K6.input.csv")).at("x");
  const VmdOptions base = GoldenOptions(ReadJsonFile(GoldenPath("vmd/gyro_like_K6.json")).at("params"));
  auto cold = DecomposeVmd(input, base);
  ASSERT_TRUE(cold.ok());
  VmdOptions opt = base;
  opt.initial_center_frequencies = cold->summary.center_frequency_cycles_per_sample;
  auto warm = DecomposeVmd(input, opt);
  ASSERT_TRUE(warm.ok());
  EXPECT_TRUE(warm->summary.converged);
  EXPECT_LT(warm->summary.iterations, cold->summary.iterations * 3 / 4);
  for (int k = 0; k < base.num_modes; ++k) {
    EXPECT_NEAR(warm->summary.center_frequency_cycles_per_sample[k], cold->summary.center_frequency_cycles_per_sample[k], 2e-3);
    double err = 0, ref = 0;
    for (std::size_t i = 0; i < input.size(); ++i) {
      err += std::pow(warm->modes[k][i] - cold->modes[k][i], 2);
      ref += input[i] * input[i];
    }
    EXPECT_LT(std::sqrt(err / ref), 2e-2) << "mode " << k + 1;  // both stop at ||du||^2/T ~ 1e-7
  }
  std::string why;
  opt.initial_center_frequencies = std::vector<double>{0.1, 0.2};
  EXPECT_FALSE(opt.IsValid(&why));
  EXPECT_NE(why.find("initial_center_frequencies"), std::string::npos);
  opt.initial_center_frequencies = std::vector<double>(6, 0.7);
  EXPECT_FALSE(DecomposeVmd(input, opt).ok());
}

TEST(Vmd, OddLengthKeepsEverySample) {
  auto x = Tone(1001, 0.02, 1.0);
  VmdOptions opt;
  opt.num_modes = 2;
  auto r = DecomposeVmd(x, opt);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->modes[0].size(), 1001u);
  EXPECT_EQ(r->summary.num_samples, 1001u);
}

TEST(Vmd, RelativeStoppingRuleAndLastIterateOptions) {
  auto x = Tone(1000, 0.03, 1.0);
  const auto y = Tone(1000, 0.2, 0.5);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] += y[i];
  VmdOptions opt;
  opt.num_modes = 2;
  opt.stopping_rule = VmdStoppingRule::kRelative;
  opt.tol = 1e-6;
  auto r = DecomposeVmd(x, opt);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->summary.converged);
  EXPECT_LE(r->summary.final_update, 1e-6);
  opt.return_last_iterate = true;
  auto last = DecomposeVmd(x, opt);
  ASSERT_TRUE(last.ok());
  EXPECT_EQ(last->summary.iterations, r->summary.iterations);
  EXPECT_NE(last->modes[0], r->modes[0]);  // a different (the next) iterate
  double worst = 0;
  for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(last->modes[0][i] - r->modes[0][i]));
  EXPECT_LT(worst, 1e-3);  // ...but a converged one: consecutive iterates are close
}

TEST(Vmd, RandomInitIsSeededAndMatchesNumpyLegacyStream) {
  auto x = Tone(800, 0.1, 1.0);
  VmdOptions opt;
  opt.num_modes = 3;
  opt.init = VmdInit::kRandom;
  opt.seed = 42;
  // One update: the reference returns the iterate before it, i.e. the initial centre
  // frequencies, which is what this test checks.
  opt.max_iterations = 2;
  auto a = DecomposeVmd(x, opt);
  ASSERT_TRUE(a.ok());
  // np.random.seed(42); np.random.rand(3) = 0.37454012, 0.95071431, 0.73199394 (8 digits
  // printed by numpy, hence the 1e-8 relative tolerance on u; omega = exp(log fs +
  // (log 0.5 - log fs) u) with fs = 1/N, sorted).
  std::vector<double> expect;
  for (double u : {0.37454012, 0.95071431, 0.73199394}) {
    expect.push_back(std::exp(std::log(1.0 / 800) + (std::log(0.5) - std::log(1.0 / 800)) * u));
  }
  std::sort(expect.begin(), expect.end());
  const auto& w = a->summary.center_frequency_cycles_per_sample;
  ASSERT_EQ(w.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(w[k], expect[k], 1e-7 * expect[k]) << k;
  opt.seed = 43;
  auto c = DecomposeVmd(x, opt);
  ASSERT_TRUE(c.ok());
  EXPECT_NE(a->summary.center_frequency_cycles_per_sample, c->summary.center_frequency_cycles_per_sample);
}

TEST(Vmd, RejectsBadOptionsAndInput) {
  VmdOptions opt;
  opt.alpha = -1;
  std::string why;
  EXPECT_FALSE(opt.IsValid(&why));
  EXPECT_EQ(why, "VmdOptions::alpha = -1: must be > 0 and finite");
  const std::vector<double> x(100, 1.0);
  auto r = DecomposeVmd(x, opt);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().kind, ErrorKind::kInvalidArgument);
  opt = VmdOptions{};
  opt.num_modes = 0;
  EXPECT_FALSE(opt.IsValid(&why));
  std::vector<double> bad(100, 0.0);
  bad[17] = std::nan("");
  auto r2 = DecomposeVmd(bad, VmdOptions{});
  ASSERT_FALSE(r2.ok());
  EXPECT_EQ(r2.error().kind, ErrorKind::kInvalidInput);
  EXPECT_NE(r2.error().message.find("17"), std::string::npos);
  auto r3 = DecomposeVmd(std::vector<double>{1, 2, 3}, VmdOptions{});
  EXPECT_FALSE(r3.ok());
}

// K is bounded by what the record supports, before any allocation (`--modes 100000`
// ran for minutes; a huge K x N ends in std::bad_alloc).
TEST(Vmd, RefusesMoreModesThanTheRecordHoldsOrMemoryAllows) {
  const std::vector<double> x(100, 1.0);
  VmdOptions opt;
  opt.num_modes = 51;  // N / 2 = 50
  auto r = DecomposeVmd(x, opt);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().kind, ErrorKind::kInvalidArgument);
  EXPECT_NE(r.error().message.find("at most 50 modes"), std::string::npos) << r.error().message;
  opt.num_modes = 50;
  opt.max_iterations = 3;
  EXPECT_TRUE(DecomposeVmd(x, opt).ok());
  // 56 x 6 x 100 = 33,600 bytes needed: refused under a 32 KiB cap, with the estimate.
  opt.num_modes = 6;
  opt.max_memory_bytes = 32 * 1024;
  auto m = DecomposeVmd(x, opt);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.error().message.find("max_memory_bytes"), std::string::npos) << m.error().message;
  opt.max_memory_bytes = 34 * 1024;
  EXPECT_TRUE(DecomposeVmd(x, opt).ok());
}

// VmdOptions::cancel is polled before every update; a cancel from another thread (a
// Python Ctrl-C, a Dask cancel) stops the decomposition with Cancelled.
TEST(VmdCancel, ThrowsCancelledAtTheNextUpdate) {
  std::vector<double> x(4096);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.01 * static_cast<double>(i)) + std::sin(0.3 * static_cast<double>(i));
  CancellationToken token;
  VmdOptions o;
  o.num_modes = 3;
  o.max_iterations = 100000;
  o.tol = 1e-300;
  o.cancel = &token;
  int updates = 0;
  o.on_iteration = [&](int, double) {
    if (++updates == 5) token.Cancel();
  };
  EXPECT_THROW((void)DecomposeVmd(x, o), Cancelled);
  EXPECT_EQ(updates, 5);
}

}  // namespace
}  // namespace gyrocomp
