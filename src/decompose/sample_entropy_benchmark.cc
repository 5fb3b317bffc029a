// Sample entropy timings (goals: N = 100,000 in 0.2 s, N = 1,000,000 in 5 s, whatever
// the entropy). Inputs: white noise (high entropy, few matches), a smooth narrow-band VMD-like
// mode (nearly every pair matches: the O(N^2) trap for pair-walking methods), and quantized
// noise (ADIS16405-like 0.05 deg/s steps: ties at distance r). m = 2, r = 0.2 SD.
//   build-<you>/sample_entropy_benchmark --benchmark_filter=Fast
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "gyrocomp/decompose/sample_entropy.h"
#include "gyrocomp/decompose/vmd.h"
#include "sample_entropy_window.h"

namespace {

std::vector<double> MakeInput(int kind, std::size_t n) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0, 1);
  std::vector<double> x(n);
  double phase = 0;
  for (std::size_t i = 0; i < n; ++i) {
    switch (kind) {
      case 0: x[i] = g(rng); break;
      case 1:  // narrow-band mode: centre 0.01 cycles/sample, slowly wandering phase
        phase += 2 * std::numbers::pi * 0.01 + 0.01 * g(rng);
        x[i] = std::cos(phase);
        break;
      default: x[i] = std::round(g(rng) * 0.1 / 0.05) * 0.05; break;
    }
  }
  return x;
}

void BM_SampleEntropyFast(benchmark::State& state) {
  const auto x = MakeInput(static_cast<int>(state.range(1)), static_cast<std::size_t>(state.range(0)));
  double se = 0;
  for (auto _ : state) {
    auto r = gyrocomp::SampleEntropy(x);
    se = r.ok() ? r->sample_entropy : -1;
    benchmark::DoNotOptimize(se);
  }
  state.counters["SampEn"] = se;
  state.SetLabel(state.range(1) == 0 ? "white" : state.range(1) == 1 ? "narrow-band" : "quantized");
}
BENCHMARK(BM_SampleEntropyFast)
    ->ArgsProduct({{10000, 100000, 1000000}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The two exact counters forced, single-threaded (the crossover that sets kFast's choice,
// sample_entropy.cc kWindowPairsPerTemplate): range counting (arg 2 = 0) vs sorted window (1).
// Counters W/template and checks/template: the window's candidate pairs and coordinate
// comparisons per template (kFast's criterion).
void BM_SampleEntropyCounter(benchmark::State& state) {
  const auto x = MakeInput(static_cast<int>(state.range(1)), static_cast<std::size_t>(state.range(0)));
  const double r = 0.2 * gyrocomp::PopulationSd(x);
  const auto algorithm = state.range(2) == 0 ? gyrocomp::SampleEntropyAlgorithm::kRangeCount
                                             : gyrocomp::SampleEntropyAlgorithm::kSortedWindow;
  for (auto _ : state) {
    auto c = gyrocomp::CountTemplateMatches(x, 2, r, algorithm, 1);
    benchmark::DoNotOptimize(c.a);
  }
  const std::vector<std::uint32_t> order = gyrocomp::se_detail::OrderByValue(x);
  const auto plan = gyrocomp::se_detail::PlanWindow(x, order, x.size() - 2, 2, r);
  state.counters["W/template"] = static_cast<double>(plan.pairs) / (x.size() - 2);
  state.counters["checks/template"] = static_cast<double>(plan.coordinate_checks) / (x.size() - 2);
  std::size_t distinct = 1;
  for (std::size_t k = 1; k < order.size(); ++k) distinct += x[order[k]] != x[order[k - 1]];
  state.counters["distinct"] = static_cast<double>(distinct) / order.size();
  state.SetLabel(std::string(state.range(1) == 0 ? "white" : state.range(1) == 1 ? "narrow-band" : "quantized") +
                 (state.range(2) == 0 ? " range" : " window"));
}
BENCHMARK(BM_SampleEntropyCounter)
    ->ArgsProduct({{2000, 20000, 50000, 100000, 200000}, {0, 1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

// The six modes of one VMD decomposition (what `decompose` measures): bench/side_by_side.py's
// record structure, N = 20,000 (white noise 0.05, a sine of period 0.7 N of amplitude 0.2, a
// ramp of 0.01; here from std::mt19937, so not its exact values), K = 6, alpha = 2000,
// tol = 1e-7; m = 2, r = 0.2 SD of each mode, one thread. arg: 0 kFast, 1 range counting,
// 2 sorted window. The decomposition runs once, outside the timing.
const std::vector<std::vector<double>>& VmdModes() {
  static const std::vector<std::vector<double>> modes = [] {
    const std::size_t n = 20000;
    std::mt19937 rng(1);
    std::normal_distribution<double> g(0, 0.05);
    std::vector<double> x(n);
    for (std::size_t i = 0; i < n; ++i) {
      x[i] = 0.2 * std::sin(2 * std::numbers::pi * i / (0.7 * n)) + 0.01 * i / n + g(rng);
    }
    gyrocomp::VmdOptions o;
    o.num_modes = 6;
    o.tol = 1e-7;
    auto v = gyrocomp::DecomposeVmd(x, o);
    return v.ok() ? v->modes : std::vector<std::vector<double>>{};
  }();
  return modes;
}

void BM_SampleEntropyOfVmdModes(benchmark::State& state) {
  const auto algorithm = state.range(0) == 0   ? gyrocomp::SampleEntropyAlgorithm::kFast
                         : state.range(0) == 1 ? gyrocomp::SampleEntropyAlgorithm::kRangeCount
                                               : gyrocomp::SampleEntropyAlgorithm::kSortedWindow;
  const auto& modes = VmdModes();
  if (modes.empty()) {
    state.SkipWithError("VMD failed");
    return;
  }
  for (auto _ : state) {
    for (const auto& u : modes) {
      auto c = gyrocomp::CountTemplateMatches(u, 2, 0.2 * gyrocomp::PopulationSd(u), algorithm, 1);
      benchmark::DoNotOptimize(c.a);
    }
  }
  for (std::size_t k = 0; k < modes.size(); ++k) {  // the window's coordinate checks per template
    const auto& u = modes[k];
    const auto plan = gyrocomp::se_detail::PlanWindow(u, gyrocomp::se_detail::OrderByValue(u), u.size() - 2, 2,
                                                      0.2 * gyrocomp::PopulationSd(u));
    state.counters["checks" + std::to_string(k + 1)] = static_cast<double>(plan.coordinate_checks) / (u.size() - 2);
  }
  state.SetLabel(state.range(0) == 0 ? "fast (chosen per mode)" : state.range(0) == 1 ? "range counting" : "window");
}
BENCHMARK(BM_SampleEntropyOfVmdModes)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

void BM_SampleEntropyBruteForce(benchmark::State& state) {
  const auto x = MakeInput(1, static_cast<std::size_t>(state.range(0)));
  gyrocomp::SampleEntropyOptions opt;
  opt.algorithm = gyrocomp::SampleEntropyAlgorithm::kBruteForce;
  for (auto _ : state) {
    auto r = gyrocomp::SampleEntropy(x, opt);
    benchmark::DoNotOptimize(r.ok());
  }
}
BENCHMARK(BM_SampleEntropyBruteForce)->Arg(10000)->Arg(30000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
