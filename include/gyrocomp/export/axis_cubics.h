// The cubics `gyrocomp export --format px4 / ardupilot` writes for three axis drift models
// (docs/explanation/flight-controller-export.md): every axis projected onto one temperature
// range, the one the models share (the autopilots have one range per sensor), or, where the
// static curve says temperature (static_weight.h), the calibration run's static curve with each
// temperature alike; the cost of each cubic measured on the runs given and its expected next-run
// error. The CLI and the Python export_params call this.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/export/c_export.h"
#include "gyrocomp/export/cubic_score.h"
#include "gyrocomp/export/static_weight.h"
#include "gyrocomp/export/thermal_cubic.h"
#include "gyrocomp/io/gyro_log.h"

namespace gyrocomp {

// What ExportAxisCubics does with the runs it is given.
struct AxisCubicsOptions {
  // The static curve exported per axis: kAuto (the estimator with the lower expected next-run
  // error; the model's own curve without a calibration run), kTemperature (the calibration run's
  // static curve, each temperature alike; needs the run), kTime (the model's own curve).
  StaticWeight static_weight = StaticWeight::kAuto;
};

// One axis's exported cubic and what it costs.
struct AxisCubic {
  TemperatureCubic cubic_dps;  // deg/s, over the shared range
  std::optional<CubicProjectionCost> calibration;  // RMS(full model - cubic) on the calibration run (nullopt: none)
  std::optional<CubicProjectionCost> validation;   // the same on the validation run (nullopt: none)
  // The cubic's expected next-run error (model band + projection): steady always, warm-up on the
  // heating of the calibration run; nullopt with the reason for a model without a band.
  std::optional<CubicExpectedError> expected;
  std::string expected_reason;  // why `expected` is missing ("" when present)
  std::string weight = "time";  // the static curve's estimator: "time" | "temperature"
  // kAuto with a calibration run: both estimators' expected errors and the choice.
  std::optional<StaticWeightChoice> weight_choice;
  std::string weight_reason;  // why the model's own curve was kept without a comparison ("" otherwise)
};

// The rate of axis `k` of `n` models in a run: its column named as the model's rate column, else
// the k-th rate column when the run has one per model; nullptr: none.
const std::vector<double>* AxisValues(const GyroLog& run, const DriftModel& model, std::size_t k, std::size_t n);

// Projects every axis onto the range the models share and chooses its static curve
// (options.static_weight); the costs on `calibration` and `validation` when given (nullptr: none;
// each needs temp_c). Errors: kInvalidArgument for kTemperature without a calibration run,
// kInvalidInput when that run has no column for an axis, the projection's and estimators' errors.
Result<std::vector<AxisCubic>> ExportAxisCubics(const std::vector<AxisDriftModel>& axes, const GyroLog* calibration,
                                                const GyroLog* validation, const AxisCubicsOptions& options = {});

}  // namespace gyrocomp
