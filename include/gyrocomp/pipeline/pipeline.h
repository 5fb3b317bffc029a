// The parallel VMD-SE-WFLP-CS-SVR model end to end (paper Section 3.5; method.md section 5):
//
//   rate --VMD--> K modes --sample entropy--> drift (C1) | mixed (C2) | noise-only (C3)
//   C3                  -> discarded
//   C2                  -> WFLP                          (denoising branch)
//   C1                  -> C1 - drift_model(T [, dT/dt]) (compensation branch, CS-SVR)
//   compensated         =  WFLP(C2) + (C1 - drift_model(T))
// The two branches run concurrently. Allan analysis before and after, and the processing's
// effective bandwidth, measured (not assumed) by passing sines through it.
//
// Also the serial scheme the paper argues against (WFLP on the whole record, then one drift model
// of the denoised record), for `gyrocomp compare`.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyrocomp/allan/allan.h"
#include "gyrocomp/denoise/bandwidth.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/decompose/feature_classifier.h"
#include "gyrocomp/decompose/sample_entropy.h"
#include "gyrocomp/core/status.h"
#include "gyrocomp/decompose/vmd.h"
#include "gyrocomp/denoise/wflp.h"

namespace gyrocomp {

// Progress of the long stages ("vmd", "entropy", "drift-fit", "bandwidth", ...): fraction in
// [0, 1] of that stage. Called from the pipeline's thread.
using ProgressCallback = std::function<void(const std::string& stage, double fraction)>;

// Default of PipelineOptions::entropy_max_samples, shared with `decompose` (samples).
inline constexpr std::size_t kDefaultEntropyMaxSamples = 200000;

// The settings of every stage of the parallel model (and of the serial scheme).
struct PipelineOptions {
  // VMD (its fs_hz is set from the record). Defaults: K = 6, alpha = 2000, tau = 0, tol = 1e-7.
  VmdOptions vmd;
  // Sample entropy of each mode (m = 2, r = 0.2 x the mode's SD by default).
  SampleEntropyOptions entropy;
  // Sample entropy is computed on at most this many samples of each mode (a contiguous window
  // from the middle of the record); nullopt = all samples. Exact SampEn is O(N log^2 N) here,
  // so this only trims time on very long records.
  std::optional<std::size_t> entropy_max_samples = kDefaultEntropyMaxSamples;
  // drift / mixed / noise thresholds: the standard-scale rule by default (docs/explanation/classification.md).
  ClassifierOptions classifier = ClassifierOptions::Standard();
  // If no mode is classified drift, the mode with the lowest centre frequency becomes the drift
  // feature (the compensation branch needs one); recorded in the result. Off: no compensation.
  bool force_drift_mode = true;
  // Denoising branch (WFLP, default db4 level 4, FLP order 8).
  WflpOptions wflp;
  // Compensation branch: cs-svr on temperature by default.
  DriftFitOptions drift;
  // Allan analysis of the raw and compensated records.
  AllanOptions allan;
  // Effective bandwidth: measured on a segment of the record (VMD + the same mode classes +
  // WFLP) by BandwidthOptions' sine-injection method. Off: bandwidth_hz absent.
  bool measure_bandwidth = true;
  std::size_t bandwidth_segment_samples = 1u << 14;  // segment length, samples, >= 1024
  int bandwidth_frequencies = 12;  // number of test frequencies, >= 4
  // Threads of every stage that uses them: VMD, sample entropy (modes measured in parallel), the
  // cuckoo search of the drift fit, and the two branches of step 3 (1 = one after the other).
  // Overrides the stages' own num_threads. nullopt = each stage's automatic choice. The results do
  // not depend on it (each stage is deterministic for any thread count). >= 1 when set.
  std::optional<int> num_threads;
  // Checks every stage's options too; the message names the field
  // ("PipelineOptions::bandwidth_frequencies = 2: must be >= 4").
  bool IsValid(std::string* error) const;
};

// A record to process: uniformly sampled rate (deg/s) and temperature (deg C).
struct PipelineInput {
  std::span<const double> rate_dps;  // gyro rate, deg/s
  std::span<const double> temp_c;    // sensor temperature, deg C, same length
  double fs_hz = 0.0;                // sample rate, Hz, > 0
  // A rate known to be applied during the run (Earth rate, turntable), deg/s, per sample; empty
  // when none. It is subtracted from the drift feature before the drift model is fitted, so the
  // model learns bias only, and it is kept in the output.
  std::span<const double> known_rate_dps;
};

// One VMD mode as the result reports it.
struct ModeReport {
  int index = 0;  // 1-based, algorithm order
  double center_frequency_hz = 0.0;                 // centre frequency, Hz
  double center_frequency_cycles_per_sample = 0.0;  // the same in cycles per sample
  double sample_entropy = 0.0;                      // SE of the mode
  FeatureClass feature = FeatureClass::kMixed;      // class given (after force_drift_mode)
};

// Everything the parallel model produced, stage by stage.
struct PipelineResult {
  double fs_hz = 0.0;                      // sample rate of the record, Hz
  std::size_t num_samples = 0;             // N
  VmdSummary vmd;                          // step 1: what the VMD did
  std::vector<std::vector<double>> modes;  // K x N (kept for reports)
  std::vector<ModeReport> mode_reports;    // step 2: one per mode
  std::string classification_rule;         // ClassificationResult::rule_text
  bool drift_mode_forced = false;          // see PipelineOptions::force_drift_mode
  FeatureSignals features;                 // C1 drift, C2 mixed, C3 noise
  std::vector<double> mixed_denoised;      // WFLP(C2)
  WflpSummary wflp;                        // what WFLP did on C2
  std::optional<DriftModel> drift_model;   // absent when there was no drift feature
  std::vector<double> predicted_drift_dps;  // drift_model(T) per sample, deg/s (empty without one)
  std::vector<double> compensated_dps;     // the output
  AllanResult allan_before;                // Allan analysis of rate_dps
  AllanResult allan_after;                 // Allan analysis of compensated_dps
  std::optional<BandwidthResult> bandwidth;  // nullopt when not measured
  std::map<std::string, double> timings_s;  // per stage, wall clock
  std::vector<std::string> warnings;       // e.g. VMD not converged, drift mode forced
  // "parallel model, N=.. at .. Hz; VMD ...", the classes, the drift model, ARW and ADEV minimum
  // before -> after, the bandwidth.
  std::string BriefReport() const;
};

// Runs the parallel model. Errors: lengths differ, fewer samples than the stages need, non-finite
// values (kInvalidInput); invalid options (kInvalidArgument); a stage's own errors pass through.
Result<PipelineResult> RunParallelModel(const PipelineInput& input,
                                        const PipelineOptions& options = {},
                                        const ProgressCallback& progress = {});

// The serial scheme: WFLP on the whole record, then one drift model of the denoised record
// against temperature, compensated = denoised - model(T).
struct SerialResult {
  std::vector<double> denoised;             // WFLP of the whole record, deg/s
  std::optional<DriftModel> drift_model;    // of `denoised` less known_rate_dps, against T
  std::vector<double> predicted_drift_dps;  // drift_model(T) per sample, deg/s
  std::vector<double> compensated_dps;      // denoised - predicted_drift_dps
  double seconds = 0.0;                     // wall-clock time, s
};
// Runs the serial scheme on `input` with the same stage options. Errors: as RunParallelModel's.
Result<SerialResult> RunSerialModel(const PipelineInput& input, const PipelineOptions& options = {});

}  // namespace gyrocomp
