#include "gyrocomp/pipeline/pipeline.h"

#include <cmath>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/sim/simulator.h"

namespace gyrocomp {
namespace {

double Rmse(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s / static_cast<double>(a.size()));
}

// A short chamber run (about 3.3 h at 2 Hz, 24,000 samples): room hold, heat to 60 C, steps of
// 25 C down to -40 C with 20-minute holds. Short enough for the sanitizer build, long enough for a
// drift model to see the whole temperature range.
SimulatedRun ShortChamberRun(std::uint64_t seed) {
  SimulatorOptions o;
  o.fs_hz = 2.0;
  o.seed = seed;
  o.profile.room_hold_s = 1200;
  o.profile.hold_s = 1200;
  o.profile.step_c = 25;
  o.profile.ramp_rate_c_per_min = 2.0;
  o.thermal_lag_s = 300;
  Result<SimulatedRun> run = Simulate(o);
  EXPECT_TRUE(run.ok()) << (run.ok() ? "" : run.error().message);
  return std::move(*run);
}

PipelineOptions FastOptions() {
  PipelineOptions o;
  // A small cuckoo-search budget keeps the test quick; the default budget is benchmarked.
  o.drift.search.cuckoo.num_nests = 6;
  o.drift.search.cuckoo.max_generations = 3;
  o.bandwidth_segment_samples = 4096;
  // This short profile ramps at 2 C/min, so the simulator's dT/dt drift term (1.5 deg/s per C/s)
  // reaches 0.05 deg/s: a temperature-only model cannot represent it (measured on seed 7: drift
  // RMSE against the truth 0.027 deg/s with temp only, 0.012 with temp and dT/dt, truth RMS
  // 0.046). The paper's temp-only input is the library default; here the test is of the
  // pipeline, so it gives the model the input the data needs.
  o.drift.inputs = DriftInputSet::kTempAndRate;
  o.bandwidth_frequencies = 6;
  return o;
}

TEST(ParallelModel, CompensatedOutputIsCloserToTheTruthThanTheRaw) {
  const SimulatedRun run = ShortChamberRun(7);
  const PipelineInput in{run.rate_dps, run.temp_c, run.fs_hz, {}};
  Result<PipelineResult> r = RunParallelModel(in, FastOptions());
  ASSERT_TRUE(r.ok()) << r.error().message;
  const std::size_t n = run.num_samples();
  ASSERT_EQ(r->compensated_dps.size(), n);
  ASSERT_EQ(r->modes.size(), 6u);
  ASSERT_EQ(r->mode_reports.size(), 6u);
  ASSERT_TRUE(r->drift_model.has_value());

  // The truth of the compensated output is the applied rate (zero here): what is left is noise.
  const double raw_error = Rmse(run.rate_dps, run.true_rate_dps);
  const double out_error = Rmse(r->compensated_dps, run.true_rate_dps);
  EXPECT_LT(out_error, 0.5 * raw_error) << "raw " << raw_error << " out " << out_error;

  // The drift branch: drift feature minus model = residual drift; against the true drift the
  // model must explain most of it (the true drift spans about 0.1 deg/s here).
  std::vector<double> residual_truth(n);
  for (std::size_t i = 0; i < n; ++i) residual_truth[i] = run.true_drift_dps[i];
  EXPECT_LT(Rmse(r->predicted_drift_dps, residual_truth), 0.5 * Rmse(residual_truth, std::vector<double>(n, 0.0)));

  // Reconstruction identity: output = WFLP(mixed) + drift - predicted.
  for (std::size_t i = 0; i < n; i += 997) {
    EXPECT_DOUBLE_EQ(r->compensated_dps[i],
                     r->mixed_denoised[i] + (r->features.drift[i] - r->predicted_drift_dps[i]));
  }
  // Allan figures and stage timings are reported.
  ASSERT_TRUE(r->allan_before.terms.arw_deg_per_sqrt_h.has_value());
  ASSERT_TRUE(r->allan_after.terms.arw_deg_per_sqrt_h.has_value());
  EXPECT_LT(*r->allan_after.terms.arw_deg_per_sqrt_h, *r->allan_before.terms.arw_deg_per_sqrt_h);
  for (const char* stage : {"vmd", "entropy", "wflp", "drift_fit", "allan", "bandwidth", "total"}) {
    EXPECT_TRUE(r->timings_s.count(stage)) << stage;
  }
  ASSERT_TRUE(r->bandwidth.has_value());
  EXPECT_GT(r->bandwidth->num_runs, 0u);
}

TEST(ParallelModel, KnownRateIsKeptInTheOutput) {
  // An Earth-rate-like constant applied during the run is subtracted before fitting, so the model
  // learns bias only and the output keeps the real rate.
  SimulatedRun run = ShortChamberRun(11);
  const double earth_dps = 15.04 / 3600.0 * 0.7;
  std::vector<double> known(run.num_samples(), earth_dps);
  for (std::size_t i = 0; i < run.num_samples(); ++i) run.rate_dps[i] += earth_dps;
  PipelineOptions o = FastOptions();
  o.measure_bandwidth = false;
  Result<PipelineResult> r = RunParallelModel({run.rate_dps, run.temp_c, run.fs_hz, known}, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const double mean = std::accumulate(r->compensated_dps.begin(), r->compensated_dps.end(), 0.0) /
                      static_cast<double>(r->compensated_dps.size());
  // The mean of the output is the known rate to within the residual drift and flicker (a few
  // 1e-4 deg/s over this short run); without the known rate it would be fitted away to ~0.
  EXPECT_NEAR(mean, earth_dps, 1e-3);
}

TEST(SerialModel, DenoisesThenCompensates) {
  const SimulatedRun run = ShortChamberRun(3);
  Result<SerialResult> r = RunSerialModel({run.rate_dps, run.temp_c, run.fs_hz, {}}, FastOptions());
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_LT(Rmse(r->compensated_dps, run.true_rate_dps), 0.5 * Rmse(run.rate_dps, run.true_rate_dps));
}

TEST(ParallelModel, RejectsBadInput) {
  std::vector<double> rate(1000, 0.0), temp(999, 20.0);
  Result<PipelineResult> r = RunParallelModel({rate, temp, 10.0, {}});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().kind, ErrorKind::kInvalidInput);
  temp.push_back(20.0);
  rate[500] = std::nan("");
  r = RunParallelModel({rate, temp, 10.0, {}});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("sample 500"), std::string::npos);
  PipelineOptions bad;
  bad.vmd.alpha = -1;
  rate[500] = 0.0;
  r = RunParallelModel({rate, temp, 10.0, {}}, bad);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().kind, ErrorKind::kInvalidArgument);
  PipelineOptions zero_threads;
  zero_threads.num_threads = 0;
  r = RunParallelModel({rate, temp, 10.0, {}}, zero_threads);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("num_threads"), std::string::npos) << r.error().message;
}

TEST(ParallelModel, ThreadCountDoesNotChangeResults) {
  // One thread (every stage, the two branches one after the other) against two: the same bits.
  const SimulatedRun run = ShortChamberRun(5);
  const PipelineInput in{run.rate_dps, run.temp_c, run.fs_hz, {}};
  PipelineOptions one = FastOptions(), two = FastOptions();
  one.num_threads = 1;
  two.num_threads = 2;
  Result<PipelineResult> a = RunParallelModel(in, one);
  Result<PipelineResult> b = RunParallelModel(in, two);
  ASSERT_TRUE(a.ok()) << a.error().message;
  ASSERT_TRUE(b.ok()) << b.error().message;
  EXPECT_EQ(a->vmd.iterations, b->vmd.iterations);
  ASSERT_EQ(a->mode_reports.size(), b->mode_reports.size());
  for (std::size_t k = 0; k < a->mode_reports.size(); ++k) {
    EXPECT_EQ(a->mode_reports[k].sample_entropy, b->mode_reports[k].sample_entropy) << k;
  }
  EXPECT_EQ(a->modes, b->modes);
  EXPECT_EQ(a->compensated_dps, b->compensated_dps);
  EXPECT_EQ(a->predicted_drift_dps, b->predicted_drift_dps);
  EXPECT_EQ(a->allan_after.curve.adev_dps, b->allan_after.curve.adev_dps);
}

}  // namespace
}  // namespace gyrocomp
