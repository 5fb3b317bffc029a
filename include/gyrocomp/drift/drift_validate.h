// A drift model on a run it was not fitted on (`gyrocomp validate`, `fit --validate`): what it
// removed, what it missed, and where the run left the calibration's conditions.
//
//   compensated = rate - predicted drift
//   residual drift: the compensated rate averaged over block_s blocks (white noise averaged
//     out), about its mean: its RMS, and its least-squares slopes against T and dT/dt
//     (residual = c0 + c1 T + c2 dT/dt over the block means): what the model missed;
//   ADEV of the compensated and raw rates at tau >= min_tau_s (overlapping ADEV, allan.h);
//   errors against truth columns when present (simulator output: true_drift_dps);
//   out-of-range: share of samples with T, and with dT/dt, outside the fitted ranges.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"

namespace gyrocomp {

struct DriftValidationOptions {
  // Block length of the residual drift (s); 100 s averages the white noise of a 5 Hz MEMS gyro
  // by sqrt(500) and keeps the drift (periods of many minutes).
  double block_s = 100.0;
  // ADEV compared at tau >= this (s).
  double min_tau_s = 100.0;
  // Evaluate the model causally (DriftEvaluator), as firmware would.
  bool causal = false;
  bool IsValid(std::string* error) const;
};

struct DriftValidation {
  std::size_t num_samples = 0;
  double fs_hz = 0.0;
  std::size_t num_blocks = 0;
  double raw_drift_rms = 0.0;          // block means of the raw rate about their mean, target units
  double residual_drift_rms = 0.0;     // same for the compensated rate
  double residual_mean = 0.0;          // mean of the compensated rate (bias left + any true rate)
  double slope_vs_temp = 0.0;          // residual per deg C
  double slope_vs_dtemp = 0.0;         // residual per (deg C / s)
  std::vector<double> tau_s, adev_raw, adev_compensated;  // tau >= min_tau_s
  std::optional<double> rmse_vs_true_drift;   // when a truth column was given
  double fraction_temp_outside = 0.0;
  double fraction_dtemp_outside = 0.0;
  TemperatureExcursion excursion;
  // The model's prediction band on this run (issue 23; absent when the model has none): its
  // level, RMS half-width, the share of samples whose true drift lies in it (truth given), and
  // the share of residual block means (block_s) of the raw rate inside the band of block means
  // (no truth: this also counts the run's own noise, so it reads low).
  std::optional<double> band_level, band_half_width_rms, band_coverage_truth, band_coverage_blocks;
  std::string BriefReport() const;
};

// `rate` and `temp_c` at fs_hz; `true_drift` empty or one value per sample.
Result<DriftValidation> ValidateDriftModel(const DriftModel& model, std::span<const double> rate,
                                           std::span<const double> temp_c, double fs_hz,
                                           std::span<const double> true_drift,
                                           const DriftValidationOptions& options = {});

}  // namespace gyrocomp
