// Drift-model fitting time on the paper's chamber run (14.25 h at 5 Hz, simulator defaults):
// `fit --model cs-svr` must finish within 60 s on 2 cores. Counters: the blocked CV
// RMSE reached (deg/s) and the number of parameter sets tried, so budgets can be compared.
//   ./drift_model_benchmark --benchmark_filter=CsSvr
#include <benchmark/benchmark.h>

#include <cstdlib>

#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/sim/simulator.h"

namespace gyrocomp {
namespace {

const SimulatedRun& PaperRun() {
  static const SimulatedRun run = [] {
    SimulatorOptions o;
    o.fs_hz = 5.0;
    o.seed = 1;
    auto r = Simulate(o);
    if (!r.ok()) std::abort();
    return std::move(*r);
  }();
  return run;
}

void Fit(benchmark::State& state, DriftFitOptions o) {
  const SimulatedRun& run = PaperRun();
  double cv = 0.0, evals = 0.0, nsv = 0.0;
  for (auto _ : state) {
    auto m = FitDriftModel({run.temp_c, run.fs_hz}, run.rate_dps, o);
    if (!m.ok()) {
      state.SkipWithError(m.error().message.c_str());
      return;
    }
    cv = m->summary.cv_rmse;
    evals = static_cast<double>(m->summary.evaluations);
    nsv = static_cast<double>(m->summary.num_support);
  }
  state.counters["cv_rmse_dps"] = cv;
  state.counters["parameter_sets"] = evals;
  state.counters["support_vectors"] = nsv;
}

// CS-SVR with `generations` generations of the default 15 nests (10 = the library default).
void BM_FitCsSvr(benchmark::State& state) {
  DriftFitOptions o;
  o.model = DriftModelKind::kCsSvr;
  o.search.cuckoo.max_generations = static_cast<int>(state.range(0));
  Fit(state, o);
}
BENCHMARK(BM_FitCsSvr)->Arg(10)->Arg(3)->Arg(30)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void BM_FitGridSvr(benchmark::State& state) {
  DriftFitOptions o;
  o.model = DriftModelKind::kGridSvr;
  Fit(state, o);
}
BENCHMARK(BM_FitGridSvr)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void BM_FitSvrDefaults(benchmark::State& state) {
  DriftFitOptions o;
  o.model = DriftModelKind::kSvr;
  Fit(state, o);
}
BENCHMARK(BM_FitSvrDefaults)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void BM_FitPoly(benchmark::State& state) {
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  o.inputs = DriftInputSet::kTempAndRate;
  Fit(state, o);
}
BENCHMARK(BM_FitPoly)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

// Prediction at the full rate (256,500 samples) with the default CS-SVR's model size.
void BM_PredictSvr(benchmark::State& state) {
  const SimulatedRun& run = PaperRun();
  DriftFitOptions o;
  o.model = DriftModelKind::kSvr;
  auto m = FitDriftModel({run.temp_c, run.fs_hz}, run.rate_dps, o);
  if (!m.ok()) {
    state.SkipWithError(m.error().message.c_str());
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(m->Predict({run.temp_c, run.fs_hz}));
  state.counters["support_vectors"] = static_cast<double>(m->summary.num_support);
}
BENCHMARK(BM_PredictSvr)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

}  // namespace
}  // namespace gyrocomp
