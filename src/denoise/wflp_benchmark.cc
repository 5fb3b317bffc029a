// Timings of the denoising stage: DWT + inverse, wavelet thresholding, FLP (per sample, the
// firmware use) and WFLP, on gyro-like records of 2^16 .. 2^22 samples (11 min .. 11.6 h at 100 Hz).
#include <cmath>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "gyrocomp/denoise/flp.h"
#include "gyrocomp/denoise/wavelet.h"
#include "gyrocomp/denoise/wavelet_denoise.h"
#include "gyrocomp/denoise/wflp.h"

namespace gyrocomp {
namespace {

std::vector<double> Record(std::size_t n) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(n);
  double walk = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    walk += 1e-3 * g(rng);
    x[i] = 0.1 + walk + 0.3 * std::sin(1e-3 * static_cast<double>(i)) + 0.28 * g(rng);
  }
  return x;
}

void BM_WaveDecRec(benchmark::State& state) {
  const std::vector<double> x = Record(static_cast<std::size_t>(state.range(0)));
  const Wavelet w = *MakeWavelet("db4");
  for (auto _ : state) {
    auto d = WaveDec(x, w, ExtensionMode::kSymmetric, 4);
    auto y = WaveRec(*d, w);
    benchmark::DoNotOptimize(y->data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_WaveDecRec)->RangeMultiplier(8)->Range(1 << 16, 1 << 22)->Unit(benchmark::kMillisecond);

void BM_WaveletDenoise(benchmark::State& state) {
  const std::vector<double> x = Record(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    auto y = WaveletDenoise(x, {});
    benchmark::DoNotOptimize(y->data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_WaveletDenoise)->RangeMultiplier(8)->Range(1 << 16, 1 << 22)->Unit(benchmark::kMillisecond);

void BM_FlpPerSample(benchmark::State& state) {
  FlpOptions o;
  o.order = static_cast<int>(state.range(0));
  const std::vector<double> x = Record(1 << 16);
  FlpFilter f = *FlpFilter::Create(o);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.Process(x[i]));
    i = (i + 1) & ((1 << 16) - 1);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FlpPerSample)->Arg(4)->Arg(8)->Arg(16)->Arg(32);

void BM_Wflp(benchmark::State& state) {
  const std::vector<double> x = Record(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    auto y = WflpDenoise(x, {});
    benchmark::DoNotOptimize(y->data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_Wflp)->RangeMultiplier(8)->Range(1 << 16, 1 << 22)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace gyrocomp
