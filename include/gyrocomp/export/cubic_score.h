// How good an exported firmware cubic is: on a run it was not fitted on (the firmware's own
// formula, float32) and, before any such run, from the model's prediction band
// (DriftModel::PredictBand). docs/explanation/flight-controller-export.md, "Expected error and validation".
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/thermal_cubic.h"

namespace gyrocomp {

// Which firmware formula evaluates the cubic (param_export.h has the sources).
enum class FirmwareFormula {
  // PX4 TemperatureCompensation::calc_thermal_offsets_3D / _1D: float dT = clamp(T, TMIN, TMAX) - TREF,
  // offset = X0 + X1 dT + X2 dT^2 + X3 dT^3 in float; Correct() subtracts it.
  kPx4,
  // ArduPilot AP_InertialSensor_TCal::correct_sensor: T and Tcal clamped to [TMIN, TMAX] (float),
  // correction = p(T - 35) - p(Tcal - 35), p(x) = (GYR1 x + GYR2 x^2 + GYR3 x^3) 1e-6 in float,
  // GYRk = the cubic re-expanded about 35 C times 1e6 (ArduPilotGyrCoefficients), rounded to float.
  kArduPilot,
};

// The correction the firmware subtracts at each temperature, firmware unit, for a cubic in the
// firmware unit (rad/s, m/s^2, Pa). `cal_temp_c`: ArduPilot's INS_GYRn_CALTEMP / INS_ACCn_CALTEMP
// (the offset calibration's temperature; PX4 ignores it).
std::vector<double> FirmwareCorrection(FirmwareFormula formula, const TemperatureCubic& cubic,
                                       std::span<const double> temp_c, double cal_temp_c);

// RMS of the means of consecutive blocks of `block_rows` rows of value - correction, their mean
// removed (the constant is the boot offset calibration's; the last partial block is dropped).
// bench/imu_calibration_side_by_side.py scores the same way (10 s blocks). Errors: sizes differ,
// block_rows == 0, fewer than 2 blocks, non-finite values.
Result<double> ResidualBlockRms(std::span<const double> value, std::span<const double> correction,
                                std::size_t block_rows);

// The expected error of an exported cubic on a next run, in one operating condition, target
// unit of the model: the RMS over the condition's samples of
//   sqrt((cubic(T) - model(T, state))^2 + sd_band(T, state)^2)
// where sd_band is the standard deviation of the model's own prediction band
// (DriftModel::PredictBand, half-width / z(level)): what the cubic loses against the model plus
// what the model itself is expected to miss on another run (parameter error, model form, an
// unidentified dT/dt gain against the calibration run's rate).
struct CubicConditionError {
  double projection_rms = 0.0;  // RMS(cubic - model) over the condition
  double band_sd_rms = 0.0;     // RMS of the band's standard deviation over the condition
  double total_rms = 0.0;       // sqrt(projection_rms^2 + band_sd_rms^2)
  std::size_t num_samples = 0;  // samples of the condition
};
// The expected error of an exported cubic on a next run, steady and in warm-up (see CubicConditionError).
struct CubicExpectedError {
  double level = 0.9;  // the band's level (its half-width is z(level) sd)
  // Temperature held at each temperature of the cubic's range (dT/dt = 0, lag settled): a slow
  // ramp over the range, `grid_points` temperatures.
  CubicConditionError steady;
  // The calibration run's own heating samples (dT/dt >= min_heating_c_per_s): warm-up at the
  // board's own heating rate. nullopt without a calibration run or with no heating sample.
  std::optional<CubicConditionError> warm_up;
};
// Settings of ExpectedCubicError.
struct CubicExpectedErrorOptions {
  int grid_points = 401;                      // steady: temperatures over the range (>= 8)
  double min_heating_c_per_s = 1.0 / 300.0;   // warm-up: as StateWhileHeating
  // False with the reason in `error` when a setting is out of range.
  bool IsValid(std::string* error) const;
};
// z of a two-sided normal interval at `level` (0.9 -> 1.645): a band's half-width is z sd.
double TwoSidedZ(double level);
// The steady condition of ExpectedCubicError temperature by temperature (the report's band about
// the exported curve): at `points` temperatures over the cubic's range, cubic - model(T, 0) and the
// band's standard deviation there; sqrt(projection^2 + band_sd^2) is the expected next-run error's
// standard deviation at T, and its RMS over the grid is ExpectedCubicError's steady.total_rms.
struct CubicErrorProfile {
  double level = 0.9;  // the band's level
  std::vector<double> temp_c;  // the grid over [temp_min_c, temp_max_c]
  std::vector<double> projection;  // cubic(T) - model(T, state 0)
  std::vector<double> band_sd;  // the model's band half-width / z(level) at T
};
// CubicErrorProfile of `cubic` against `model` at `points` temperatures. Model unit, `cubic`
// before any constant is removed. Errors: as ExpectedCubicError's steady part.
Result<CubicErrorProfile> SteadyCubicErrorProfile(const DriftModel& model, const TemperatureCubic& cubic, int points = 401);
// `cubic` in the model's target unit, before any constant is removed. Errors: the model has no
// band (an older model file), invalid options, Predict errors.
Result<CubicExpectedError> ExpectedCubicError(const DriftModel& model, const TemperatureCubic& cubic,
                                              const std::optional<DriftInputs>& calibration_run,
                                              const CubicExpectedErrorOptions& options = {});

}  // namespace gyrocomp
