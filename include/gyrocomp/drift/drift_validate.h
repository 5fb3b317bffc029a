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

// How ValidateDriftModel measures a model on a run.
struct DriftValidationOptions {
  // Block length of the residual drift (s); 100 s averages the white noise of a 5 Hz MEMS gyro
  // by sqrt(500) and keeps the drift (periods of many minutes).
  double block_s = 100.0;
  // ADEV compared at tau >= this (s).
  double min_tau_s = 100.0;
  // Evaluate the model causally (DriftEvaluator), as firmware would.
  bool causal = false;
  // False with the reason in `error` when block_s or min_tau_s is not a finite value > 0.
  bool IsValid(std::string* error) const;
};

// What a drift model did on a run it was not fitted on (see the top of this file).
struct DriftValidation {
  std::size_t num_samples = 0;  // samples of the run
  double fs_hz = 0.0;  // sample rate, Hz
  std::size_t num_blocks = 0;  // blocks of block_s in the residual drift
  double raw_drift_rms = 0.0;          // block means of the raw rate about their mean, target units
  double residual_drift_rms = 0.0;     // same for the compensated rate
  double residual_mean = 0.0;          // mean of the compensated rate (bias left + any true rate)
  double slope_vs_temp = 0.0;          // residual per deg C
  double slope_vs_dtemp = 0.0;         // residual per (deg C / s)
  std::vector<double> tau_s;  // averaging times, s (tau >= min_tau_s)
  std::vector<double> adev_raw;  // overlapping ADEV of the raw rate at tau_s
  std::vector<double> adev_compensated;  // overlapping ADEV of the compensated rate at tau_s
  std::optional<double> rmse_vs_true_drift;   // when a truth column was given
  double fraction_temp_outside = 0.0;  // share of samples with T outside the fitted range
  double fraction_dtemp_outside = 0.0;  // share of samples with dT/dt outside the fitted range
  TemperatureExcursion excursion;  // how far and how long T left the fitted range
  // The model's prediction band on this run (docs/explanation/prediction-bands.md; absent when
  // the model has none): its level, RMS half-width, the share of samples whose true drift lies
  // in it (truth given), and the share of residual block means (block_s) of the raw rate inside
  // the band of block means (no truth: this also counts the run's own noise, so it reads low).
  std::optional<double> band_level;  // band level (probability)
  std::optional<double> band_half_width_rms;  // RMS half-width of the band, target units
  std::optional<double> band_coverage_truth;  // share of samples whose true drift is in the band
  std::optional<double> band_coverage_blocks;  // share of raw-rate block means inside the band of block means
  // One line for logs: residual drift RMS vs raw, slopes, out-of-range shares, band coverage.
  std::string BriefReport() const;
};

// `rate` and `temp_c` at fs_hz; `true_drift` empty or one value per sample.
Result<DriftValidation> ValidateDriftModel(const DriftModel& model, std::span<const double> rate,
                                           std::span<const double> temp_c, double fs_hz,
                                           std::span<const double> true_drift,
                                           const DriftValidationOptions& options = {});

}  // namespace gyrocomp
