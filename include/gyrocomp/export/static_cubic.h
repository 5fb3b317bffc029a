// The static curve of a calibration run, estimated with every temperature weighted alike
// (docs/explanation/flight-controller-export.md "Each temperature weighted alike").
//
// The firmware's cubic is a static curve applied equally at every temperature. A least-squares
// fit over the run's samples weighs each temperature by the time the run spent there: the holds
// at the ends of a chamber profile or a power-on warm-up outweigh the whole ramp, and any offset the
// run carries while the temperature moves (a dT/dt or lag term the model could not identify on a
// one-direction run) bends the cubic at the ends, which the opposite direction then pays for.
// Here:
//   r_i = y_i - (model(T_i, state_i) - model(T_i, 0))     the model's own dynamic part removed
//                                                         (0 for a temperature-only model)
//   the means of (T_i, r_i) in `bins` equal-width temperature bins over the range (PX4
//   Tools/process_sensor_caldata.py, resampleWithDeltaX: 2000 bins, empty bins dropped)
//   the least-squares cubic in T - ref_temp_c of the bin means, one point per non-empty bin.
#pragma once

#include <optional>
#include <span>

#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/thermal_cubic.h"

namespace gyrocomp {

// How FitStaticCubicByTemperature bins the run and over which range it fits.
struct StaticCubicOptions {
  int bins = 2000;  // equal-width temperature bins over [temp_min_c, temp_max_c] (>= 8)
  // Range (the cubic's TMIN/TMAX) and dT origin; automatic: the run's range and its middle.
  std::optional<double> temp_min_c;  // lower end, deg C
  std::optional<double> temp_max_c;  // upper end, deg C
  std::optional<double> ref_temp_c;  // dT origin, deg C
  // False with the reason in `error` when a setting is out of range.
  bool IsValid(std::string* error) const;
};

// `y` in the model's target unit, one value per sample of `run`. Errors: sizes differ, fewer than
// 4 non-empty bins, an empty range, non-finite values, Predict errors.
Result<TemperatureCubic> FitStaticCubicByTemperature(const DriftModel& model, const DriftInputs& run,
                                                     std::span<const double> y, const StaticCubicOptions& options = {});

}  // namespace gyrocomp
