// Allan deviation and simulator timings (target: 5 million samples with octave taus in about a
// second; simulating 14 h at 100 Hz in seconds).
//   build-<you>/allan_benchmark
//   build-<you>/allan_benchmark --benchmark_filter=AllanOctave/5000000
#include <benchmark/benchmark.h>

#include <vector>

#include "gyrocomp/allan/allan.h"
#include "gyrocomp/allan/deviations.h"
#include "gyrocomp/sim/simulator.h"

namespace {

std::vector<double> WhiteNoise(std::size_t n) {
  gyrocomp::NormalGenerator g(1);
  std::vector<double> y(n);
  for (double& v : y) v = 0.03 * g.Next();
  return y;
}

void RunAllan(benchmark::State& state, gyrocomp::TauGrid grid) {
  const auto y = WhiteNoise(static_cast<std::size_t>(state.range(0)));
  gyrocomp::AllanOptions o;
  o.grid = grid;
  std::size_t taus = 0;
  for (auto _ : state) {
    auto r = gyrocomp::ComputeAllan(y, 100.0, o);
    taus = r.ok() ? r->curve.size() : 0;
    benchmark::DoNotOptimize(taus);
  }
  state.counters["taus"] = static_cast<double>(taus);
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_AllanOctave(benchmark::State& state) { RunAllan(state, gyrocomp::TauGrid::kOctave); }
void BM_AllanDecade(benchmark::State& state) { RunAllan(state, gyrocomp::TauGrid::kDecade); }
void BM_AllanPerDecade10(benchmark::State& state) { RunAllan(state, gyrocomp::TauGrid::kPerDecade); }

BENCHMARK(BM_AllanOctave)->Arg(200000)->Arg(1000000)->Arg(5000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AllanDecade)->Arg(5000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AllanPerDecade10)->Arg(5000000)->Unit(benchmark::kMillisecond);

// Each deviation kind at N = 1 M, octave taus (target: each well under a second).
void BM_Deviation(benchmark::State& state) {
  const auto kind = static_cast<gyrocomp::DeviationKind>(state.range(0));
  const auto y = WhiteNoise(1000000);
  std::size_t taus = 0;
  for (auto _ : state) {
    auto r = gyrocomp::ComputeDeviation(y, 100.0, kind);
    taus = r.ok() ? r->size() : 0;
    benchmark::DoNotOptimize(taus);
  }
  state.SetLabel(gyrocomp::DeviationKindName(kind));
  state.counters["taus"] = static_cast<double>(taus);
}
BENCHMARK(BM_Deviation)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

// The default paper run: 14.25 h at 100 Hz = 5.13 million samples, every term on.
void BM_SimulatePaperRun(benchmark::State& state) {
  gyrocomp::SimulatorOptions o;
  o.fs_hz = static_cast<double>(state.range(0));
  std::size_t n = 0;
  for (auto _ : state) {
    auto r = gyrocomp::Simulate(o);
    n = r.ok() ? r->num_samples() : 0;
    benchmark::DoNotOptimize(n);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
}
BENCHMARK(BM_SimulatePaperRun)->Arg(100)->Unit(benchmark::kMillisecond);

}  // namespace
