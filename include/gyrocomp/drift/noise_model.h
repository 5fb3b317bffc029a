// Noise model of a drift fit's residual: the IEEE Std 952 gyro noise
// model, white (angle random walk) + flicker (bias instability) + rate random walk, as the
// one-sided power spectral density
//   S(f) = h0 + h_1 / f + h_2 / f^2            ((target units)^2 / Hz, f in Hz)      Eq. G-0
// fitted to the Allan variance of a residual (Eq. G-1), and the covariance of its block means that
// follows from it (Eq. G-2). The polynomial drift fit uses it for generalised least squares
// (DriftFitOptions::noise_model = kAllan; docs/explanation/drift-noise-model.md).
//
// Why: on a single calibration run the flicker of the gyro wanders over hours, like the drift;
// ordinary least squares weighs every sample as independent and absorbs that wander into the
// coefficients (docs/explanation/drift-noise-model.md: 88-99% of poly's held-out error on the simulated
// runs). Weighting by the inverse noise covariance is the best linear unbiased estimator when
// the noise model is right and the polynomial's form is right (Gauss-Markov); when the form is
// wrong (hysteresis the polynomial cannot represent), the misfit looks like flicker and GLS
// re-weights it: measured worse there (docs/explanation/drift-models.md).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyrocomp/core/status.h"

namespace gyrocomp {

// The noise model of a polynomial drift fit: white = ordinary least squares (every sample
// independent, equal variance: the default, what every earlier version did); allan = generalised
// least squares with the Eq. G-0 model fitted to the Allan variance of the OLS residual.
enum class DriftNoiseModel { kWhite, kAllan };
// "white" | "allan".
std::optional<DriftNoiseModel> ParseDriftNoiseModel(std::string_view name);
// The name ParseDriftNoiseModel reads.
const char* DriftNoiseModelName(DriftNoiseModel model);

// Eq. G-0 coefficients, one-sided PSD, (target units)^2 / Hz times f^0, f^1, f^2.
struct NoisePsd {
  double h0 = 0.0;   // white
  double h_1 = 0.0;  // flicker, coefficient of 1/f
  double h_2 = 0.0;  // random walk, coefficient of 1/f^2
  // In datasheet units for a rate in deg/s (IEEE 952; conversions in core/units.h):
  // ARW N = sqrt(h0 / 2) deg/sqrt(s) (AVAR = N^2 / tau); bias instability B = sqrt(2 ln2 h_1) /
  // 0.664 deg/s (the flicker floor of the ADEV is 0.664 B); RRW K = pi sqrt(2 h_2) deg/s/sqrt(s)
  // (AVAR = K^2 tau / 3).
  double arw_deg_per_sqrt_h() const;
  // Bias instability B, deg/h.
  double bias_instability_deg_per_h() const;
  // Rate random walk K, deg/h/sqrt(h).
  double rrw_deg_per_h_per_sqrt_h() const;
  // One line for logs: h0, h_1, h_2 and, in datasheet units, ARW, bias instability, RRW.
  std::string BriefReport() const;
};

// How the Eq. G-0 model is fitted to the Allan variance of a residual (Eq. G-1).
struct NoisePsdOptions {
  // Shortest averaging time fitted, s. Automatic: one sample. The drift fit's GLS sets it to its
  // block period: the model is fitted where it is used (a gyro's flicker floor holds over a band
  // only; below it the short-tau white would set the flicker level, measured 17% low on the
  // simulator's band-limited flicker).
  std::optional<double> min_tau_s;
  // Averaging times of the Allan variance fitted: log-spaced from min_tau_s to this fraction of
  // the record (longer taus have few independent averages and the fit's OLS residual has lost
  // its slowest content to the regressors). 0.1: the record / 10.
  double max_tau_fraction = 0.1;
  // Number of log-spaced taus (duplicates after rounding to whole samples are dropped).
  int num_taus = 30;
  // False with the reason in `error` when a setting is out of range.
  bool IsValid(std::string* error) const;
};

// Eq. G-1: fits h0, h_1, h_2 >= 0 to the overlapping Allan variance of `x` (sampled at fs_hz),
//   AVAR(tau) = h0 / (2 tau) + 2 ln2 h_1 + (2 pi^2 / 3) h_2 tau,
// by weighted least squares with weights EDF / AVAR_model^2 (EDF ~ samples / averaging factor:
// the variance of an AVAR estimate is ~ 2 AVAR^2 / EDF), iterated 4 times from the measured AVAR,
// over the non-negative coefficients (all 7 active sets of the 3 terms; the best feasible one).
// Errors: invalid options, fs_hz <= 0, fewer than 8 samples, non-finite values, a constant series.
Result<NoisePsd> FitNoisePsd(std::span<const double> x, double fs_hz, const NoisePsdOptions& options = {});

// Eq. G-2: autocovariance R(k), k = 0..n-1, of consecutive block means over block_s seconds of
// noise with the Eq. G-0 spectrum:
//   R(k) = h0 / (2 block_s) [k = 0]
//        + sum_{j=1}^{n} df cos(2 pi j k / (2n)) sum_a S_red(|f_j + a / block_s|) sinc^2(...),
// f_j = j df, df = 1 / (2 n block_s), S_red = h_1 / f + h_2 / f^2, sinc(x) = sin(pi x) / (pi x)
// of f block_s (the block mean), a = -200..200 the aliases of sampling once per block, the
// Nyquist term (j = n) halved: the
// inverse DFT on a circulant grid of 2n blocks, nothing below 1 / (2 record) (flicker and random
// walk have no finite variance; a constant added to R changes no fit that has a constant term).
// f_floor_hz > 0: S_red evaluated at max(f, f_floor_hz), i.e. the red part held flat below the
// floor (drift_band.cc: not extrapolated below the longest Allan tau fitted). 0: Eq. G-2 as above.
std::vector<double> BlockMeanAutocovariance(const NoisePsd& psd, std::size_t n, double block_s,
                                            double f_floor_hz = 0.0);

// Eq. G-1: the Allan variance the model gives at averaging time tau_s (IEEE 952: white
// h0 / (2 tau), flicker 2 ln2 h_-1, random walk (2 pi^2 / 3) h_-2 tau).
double ModelAllanVariance(const NoisePsd& psd, double tau_s);

// The f_floor_hz of a record of duration_s: 1 / (2 pi tau_max), tau_max = options.max_tau_fraction
// x the record, the longest Allan tau FitNoisePsd fits (the band's Eq. B-2, static_weight.h).
double RedSpectrumFloorHz(const NoisePsdOptions& options, double duration_s);

}  // namespace gyrocomp
