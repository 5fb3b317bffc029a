// The autopilots' form of a drift model: a cubic in temperature alone (PX4 TC_G*, ArduPilot
// INS_TCAL*), and the least-squares projection of any DriftModel onto it (docs/explanation/flight-controller-export.md).
//
// Projection: the model is evaluated on a uniform grid of `grid_points` temperatures over the
// range [temp_min_c, temp_max_c] (the calibrated range: clamped outside, as the firmware does),
// with the thermal state 0 for models that read one (dT/dt = 0, lag settled, no memory: the static
// curve; the firmware forms have no state),
// and the cubic in dT = T - ref_temp_c that minimises the squared error over the grid is kept.
// A grid uniform in T weighs every temperature of the range alike; the model itself was fitted
// on every sample (time-weighted), unlike PX4's process_sensor_caldata.py, which fits the means
// of 2000 equal-width temperature bins (docs/explanation/flight-controller-export.md).
//
// What that loses is measured, not assumed: CubicProjectionCost compares the full model (its own
// centred prediction, dT/dt included) with the cubic on a record (the calibration run, a
// validation run).
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string_view>
#include <vector>
#include <string>

#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"

namespace gyrocomp {

// offset(T) = c0 + c1 dT + c2 dT^2 + c3 dT^3, dT = clamp(T, temp_min_c, temp_max_c) - ref_temp_c,
// in the model's target unit (deg/s for a rate).
struct TemperatureCubic {
  double ref_temp_c = 0.0;  // reference temperature of dT, deg C
  double temp_min_c = 0.0;  // lower clamp of T, deg C
  double temp_max_c = 0.0;  // upper clamp of T, deg C
  std::array<double, 4> coeff{};  // c0..c3, target unit / C^k
  // offset(T) of the formula above, target unit.
  double Evaluate(double temp_c) const;
  // The same cubic scaled by `factor` (unit conversion: deg/s -> rad/s).
  TemperatureCubic Scaled(double factor) const;
  // The same polynomial re-expanded about `new_ref_c` (exact algebra, range unchanged):
  // sum_k c_k (x + d)^k with d = new_ref_c - ref_temp_c.
  TemperatureCubic Recentered(double new_ref_c) const;
};

// What the static cubic is optimised for. The firmware's cubic has no thermal state;
// a model that has one (dT/dt, lag, memory) gives a different curve at each state:
//   kSteady  the curve at state 0 (temperature held: dT/dt = 0, lag settled). The default.
//   kWarmUp  the curve along the board's own warm-up: at each temperature the state the
//            calibration run had while heating there (StateWhileHeating), 0 where it never heated.
//   kBoth    the least-squares cubic of both targets together (their mean).
// A temperature-only model gives the same cubic for all three.
enum class CubicCondition { kSteady, kWarmUp, kBoth };
std::optional<CubicCondition> ParseCubicCondition(std::string_view name);  // "steady" | "warm-up" | "both"
// The name ParseCubicCondition reads.
const char* CubicConditionName(CubicCondition condition);

// A model's thermal state as a function of temperature while a record heats: the median state
// of its heating samples (dT/dt >= min_heating_c_per_s, the centred dT/dt) in bins of bin_c,
// 0 in bins without any.
struct StateByTemperature {
  double t0_c = 0.0;  // lower edge of bin 0, deg C
  double bin_c = 1.0;  // bin width, deg C
  std::vector<double> state;  // median state per bin (0 in bins without heating samples)
  // The state of the bin holding temp_c (the first / last bin outside them; 0 when empty).
  double At(double temp_c) const;
};
// Errors: the record's state cannot be computed (too short, fs <= 0), non-finite values.
Result<StateByTemperature> StateWhileHeating(const DriftModel& model, const DriftInputs& record,
                                             double min_heating_c_per_s = 1.0 / 300.0, double bin_c = 1.0);
// The binning StateWhileHeating does, on rows given directly (e.g. the still rows of several
// logs): per bin_c bin from the lowest temperature, the median state of the rows heating at
// rate_c_per_s >= min_heating_c_per_s (C/s), 0 in bins without any; a row with a non-finite
// value is left out. temp_c, state and rate_c_per_s are as long as each other (state in the
// model's state unit: C/s for dT/dt, C for a lag's T - T_lag). Errors: lengths differ, bin_c <= 0.
Result<StateByTemperature> HeatingStateByTemperature(std::span<const double> temp_c, std::span<const double> state,
                                                     std::span<const double> rate_c_per_s,
                                                     double min_heating_c_per_s = 1.0 / 300.0, double bin_c = 1.0);

// How ProjectOntoCubic fits the firmware's cubic to a model.
struct CubicProjectionOptions {
  CubicCondition condition = CubicCondition::kSteady;  // which state the cubic is fitted at
  // kWarmUp / kBoth with a model that reads a state: required (StateWhileHeating of the
  // calibration run).
  std::optional<StateByTemperature> warm_up;
  // Grid temperatures over the range (>= 8). 401 points: the projection changes by less than
  // 1e-6 of the span between 401 and 4001 points for the models in the tests.
  int grid_points = 401;
  // Range to project over; automatic: the model's fitted range. Several axes exported together
  // share one range (the autopilots have one TMIN/TMAX per sensor).
  std::optional<double> temp_min_c;  // lower end, deg C
  std::optional<double> temp_max_c;  // upper end, deg C
  // dT origin; automatic: the middle of the range (PX4's process_sensor_caldata.py convention).
  std::optional<double> ref_temp_c;
  // False with the reason in `error` when a setting is out of range.
  bool IsValid(std::string* error) const;
};

// Errors: invalid options, an empty range (min >= max), a range whose span is not finite or so
// narrow (~1e-100 C and below) that a coefficient c_k (target unit / C^k) is not finite.
Result<TemperatureCubic> ProjectOntoCubic(const DriftModel& model,
                                          const CubicProjectionOptions& options = {});

// RMS and largest |full model - cubic| over a record, in the model's target unit.
struct CubicProjectionCost {
  std::size_t num_samples = 0;  // samples compared
  double rms = 0.0;  // RMS of full model - cubic, target unit
  double max_abs = 0.0;  // largest |full model - cubic|, target unit
  double model_span = 0.0;  // max - min of the full model's prediction over the record
  // One line for logs: RMS, max, samples, model span.
  std::string BriefReport() const;
};

// Errors as DriftModel::Predict.
Result<CubicProjectionCost> MeasureCubicProjectionCost(const DriftModel& model,
                                                       const TemperatureCubic& cubic,
                                                       const DriftInputs& record);

}  // namespace gyrocomp
