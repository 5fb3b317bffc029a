// The paper's comparisons (Section 4.3) on any record, plus the baselines a calibration engineer
// would ask for (method.md "Honest evaluation"):
//   denoising  the mixed feature C2 through nothing / wavelet threshold / FLP / WFLP, each output
//              recombined with the compensated drift branch: ARW, ADEV minimum, bias instability
//              and the method's effective bandwidth side by side (a lower ARW bought by a narrower
//              bandwidth is not a better denoiser);
//   drift      the drift feature C1 modelled by poly(T), poly(T, dT/dt), SVR with LIBSVM's
//              defaults, grid-searched SVR and CS-SVR (in-sample: the record they were fitted on);
//   schemes    raw vs serial (denoise, then compensate) vs parallel (the paper's).
// With ground truth (simulated records), errors against it: the output against the true rate,
// each drift model's prediction against the true drift.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyrocomp/pipeline/pipeline.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp {

// Which comparisons CompareMethods runs, with which stage settings.
struct ComparisonOptions {
  // The settings of every stage (the parallel run's, and the baselines' where they share them).
  PipelineOptions pipeline;
  // Which groups to run. Grid search costs about as much as CS-SVR.
  bool denoising = true;
  bool drift_models = true;  // the drift-model rows (C1 models against T)
  bool grid_search = true;   // the grid-searched SVR row among the drift models
  bool schemes = true;       // raw vs serial vs parallel rows
  // The serial scheme fits its own drift model by default (a second search). When set, it reuses
  // the SVR parameters (C, gamma, epsilon) the parallel run's search chose, fitting once: half the
  // cost, for `demo`'s one-minute budget. Rows say which.
  bool serial_reuses_parallel_parameters = false;
  // Bandwidth of each denoiser, measured on a segment of C2 (samples).
  std::size_t bandwidth_segment_samples = 1u << 14;
  // Checks `pipeline` too. "ComparisonOptions::bandwidth_segment_samples = 10: must be >= 1024"
  bool IsValid(std::string* error) const;
};

// Ground truth of a simulated record (empty spans when unknown).
struct ComparisonTruth {
  std::span<const double> true_rate_dps;   // applied rate per sample, deg/s
  std::span<const double> true_drift_dps;  // temperature drift per sample, deg/s
};

// One method's figures on the record (nullopt: not applicable to that method or not computed).
struct MethodRow {
  std::string group;   // "denoising" | "drift" | "scheme"
  std::string method;  // e.g. "wavelet threshold (db4, L4, universal soft)"
  std::optional<double> arw_deg_per_sqrt_h;          // angle random walk of the output
  std::optional<double> adev_min_deg_per_h;          // minimum of the output's Allan deviation
  std::optional<double> bias_instability_deg_per_h;  // bias instability of the output
  std::optional<double> bandwidth_hz;          // nullopt: not measured, or above the tested range
  std::optional<double> rmse_vs_true_rate_dps;  // output against the true rate (truth given)
  std::optional<double> drift_rmse_vs_truth_dps;  // drift model against the true drift
  std::optional<double> drift_cv_rmse_dps;     // blocked CV RMSE of a drift model
  double seconds = 0.0;  // wall-clock time of the method, s
  std::string note;      // caveats, e.g. why the bandwidth was not measured; "" when none
};

// The rows of every comparison run.
struct ComparisonResult {
  std::vector<MethodRow> rows;  // grouped, in the order above
  // One line per row: "group | method | ARW .. | ADEV min .. | BW .. Hz".
  std::string BriefReport() const;
};

// Runs the comparisons on a record already processed by RunParallelModel (`parallel`, whose
// features and drift model are reused). Errors: as the stages'.
Result<ComparisonResult> CompareMethods(const PipelineInput& input, const PipelineResult& parallel,
                                        const ComparisonTruth& truth,
                                        const ComparisonOptions& options = {});

}  // namespace gyrocomp
