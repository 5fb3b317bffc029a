// Sample entropy timings (issue 3 goals: N = 100,000 in 0.2 s, N = 1,000,000 in 5 s, whatever
// the entropy). Inputs: white noise (high entropy, few matches), a smooth narrow-band VMD-like
// mode (nearly every pair matches: the O(N^2) trap for pair-walking methods), and quantized
// noise (ADIS16405-like 0.05 deg/s steps: ties at distance r). m = 2, r = 0.2 SD.
//   build-<you>/sample_entropy_benchmark --benchmark_filter=Fast
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "gyrocomp/decompose/sample_entropy.h"

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
