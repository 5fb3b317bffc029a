// Which estimator of the static curve to export, per axis
// (docs/explanation/flight-controller-export.md "Choosing the weighting per axis
// (--static-weight auto)").
//
// Two linear estimators of the firmware's cubic from one calibration run (y = the run's values):
//   time         the least-squares cubic over every sample (what the fitted model's own curve,
//                projected, is for a model that is a polynomial in T; tempcal_IMU's np.polyfit);
//   temperature  the least-squares cubic of the means of equal-width temperature bins
//                (FitStaticCubicByTemperature; PX4's process_sensor_caldata.py).
// Each is c_w = L_w y with L_w a 4 x n matrix. With y = s(T) + g r(t) + n (s the static curve, g
// a dT/dt gain the model left out, r the run's dT/dt, n the noise), the error of c_w about s is
//   g L_w r  +  L_w n.
// The expected next-run error of each is estimated from the run's own evidence, the same
// ingredients as the model's prediction band (drift_model.h, DriftBandModel):
//   gain part  G (L_w r)(T) - G r_next(T), G = sqrt(max(0, g^2 - SE^2)) from Eq. I-1's gain and
//              jackknife SE (a model file, which keeps only Eq. B-4's band G = |g|: that; 0 when
//              the model has no left-out gain); r_next = 0 at steady temperature, the run's own dT/dt along its
//              heating (warm-up); the constant removed (the boot offset calibration's);
//   noise part a(T)' Cov_w a(T), Cov_w = sigma_white^2 L_w L_w' + Lb_w R Lb_w' with the band's
//              Eq. G-0 noise (white; flicker + random walk as block means, Eq. G-2, R of
//              blocks of the band's period, Lb the sum of L's columns in each block), the
//              design row a(T) centred over the condition's temperatures.
// The one with the lower sqrt(gain^2 + noise^2), averaged over the conditions (mean square),
// is chosen: a left-out gain that is large against its SE makes the time estimator's bent
// cubic costly; without one, the time estimator's use of the holds' samples (lower noise) wins.
// Why not ExpectedCubicError (cubic_score.h) itself: its band is centred on the model's own
// curve, so for a model that is a cubic in T the time estimator's projection loss is 0 and its
// band term is the same for both: it always picks time whatever the run shows.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/thermal_cubic.h"

namespace gyrocomp {

// Estimator of the static cubic: by temperature bins, by time (every sample), or chosen per axis.
enum class StaticWeight { kTemperature, kTime, kAuto };
std::optional<StaticWeight> ParseStaticWeight(std::string_view name);  // "temperature" | "time" | "auto"
// The name ParseStaticWeight reads.
const char* StaticWeightName(StaticWeight weight);

// One estimator's expected next-run error, model target unit, RMS over the condition(s).
struct StaticEstimatorError {
  double rate_gain_rms = 0.0;  // the left-out dT/dt gain's part: the gain x rate_shape_rms
  // RMS of what the estimator makes of the run's dT/dt less the next run's dT/dt, C/s (constant removed)
  double rate_shape_rms = 0.0;
  double noise_rms = 0.0;      // the run's noise through the estimator
  double total_rms = 0.0;      // sqrt(rate_gain_rms^2 + noise_rms^2)
};

// What --static-weight auto chose for one axis, with both estimators' expected errors.
struct StaticWeightChoice {
  StaticWeight chosen = StaticWeight::kTime;  // kTime or kTemperature
  StaticEstimatorError time;  // the time estimator's expected error
  StaticEstimatorError temperature;  // the temperature estimator's expected error
  double rate_gain_rms = 0.0;  // the gain used (model unit per C/s; 0: no left-out gain)
  // Eq. I-1's left-out gain and its SE when the model has them (a fit in memory; a model file
  // keeps only the band's G), and the band's G (the cap).
  std::optional<double> gain;  // Eq. I-1's left-out gain, model unit per C/s
  std::optional<double> gain_se;  // its SE
  double band_gain_rms = 0.0;  // the band's G (the cap), model unit per C/s
  std::string reason;          // one line: which and why
};

// Settings of the static-weight choice.
struct StaticWeightOptions {
  int bins = 2000;                           // as StaticCubicOptions::bins (>= 8)
  int grid_points = 401;                     // steady: temperatures over the range (>= 8)
  double min_heating_c_per_s = 1.0 / 300.0;  // warm-up: as StateWhileHeating
  double red_block_s = 60.0;                 // flicker / random walk as block means of this period, s (> 0)
  // False with the reason in `error` when a setting is out of range.
  bool IsValid(std::string* error) const;
};

// Per axis: both estimators' expected errors on [temp_min_c, temp_max_c] (reference its middle)
// for `condition` (kBoth: the mean of the steady and warm-up mean squares; warm-up without a
// heating sample counts as steady). Errors: the model has no band, invalid options, an empty
// range, fewer than 4 non-empty bins, the run's dT/dt cannot be computed.
Result<StaticWeightChoice> ChooseStaticWeight(const DriftModel& model, const DriftInputs& run, double temp_min_c,
                                              double temp_max_c, CubicCondition condition,
                                              const StaticWeightOptions& options = {});

// Several calibration runs of one board, their cubics averaged: the gain is common to the runs
// (the same board): estimated from all of them, g = the mean of the runs' gains, SE^2 = the mean
// of their SE^2 / runs, g^2 - SE^2 as above (capped by the runs' mean band G^2; without the
// runs' g and SE, the mean of their squared gains), times the RMS of the runs' rate shapes; the
// noise parts independent (their mean square / runs). Chooses as ChooseStaticWeight.
StaticWeightChoice CombineStaticWeightChoices(const std::vector<StaticWeightChoice>& per_run);

}  // namespace gyrocomp
