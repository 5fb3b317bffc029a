// gyrocomp calibrate's per-sensor state (tools/calibrate.cc fits it; tools/calibrate_output.cc
// writes it: the parameter file, the model files, the console table, the JSON and the report's
// curves). Internal to the CLI.
#pragma once

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "calibrate_report.h"
#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/cubic_score.h"
#include "gyrocomp/export/static_weight.h"
#include "gyrocomp/export/thermal_cubic.h"

namespace gyrocomp::cli::calibrate {

constexpr const char* kCalibrateName = "calibrate";
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

struct CalibrateArgs {
  std::string input;                      // the first -i (the primary run: models, bands, cost)
  std::vector<std::string> inputs;        // every -i: runs of one board, their cubics averaged
  std::string format;
  std::string output;
  std::string models_dir;
  std::string json_path;
  std::string validation_path;  // a second log of the same board: every exported cubic scored on it
  std::string report_path;      // HTML report
  double block_s = 10.0;        // validation: residual block means, s (bench/imu_calibration_side_by_side.py)
  double fit_rate_hz = 1.0;   // block means of the rows before fitting
  double min_span_c = 10.0;   // ArduPilot's TEMP_RANGE_MIN (AP_InertialSensor_tempcal.cpp)
  std::size_t min_rows = 60;  // after the block means
  std::string optimise_for = "steady";  // CubicCondition of the exported cubic
  // How the static curve is estimated: "temperature" (each temperature alike: the run's data,
  // the model's dynamic part removed, in equal-width temperature bins; static_cubic.h), "time"
  // (the fitted model's own curve at state 0, fitted on every sample) or "auto" (per axis, the
  // one with the lower expected next-run error; static_weight.h).
  std::string static_weight = "auto";
};

// One sensor instance of the log, in its sensor frame and firmware unit.
struct Sensor {
  std::string type;  // gyro | accel | baro
  int instance = 0;
  std::optional<std::uint32_t> device_id;
  std::vector<double> time_s, temp_c;
  std::vector<std::vector<double>> values;  // per axis, firmware unit (rad/s, m/s^2, Pa)
  std::vector<std::string> cols;            // x_rad_s | x_m_s2 | pressure_pa
  std::string unit;                         // firmware unit
  double to_model = 1.0;                    // firmware unit -> model unit (gyro: deg/s)
  std::string model_unit;
  // Outcome.
  std::string reason;  // non-empty: skipped
  int slot = -1;       // PX4 slot / ArduPilot IMU n
  std::vector<DriftModel> models;
  std::vector<TemperatureCubic> cubics;  // firmware unit, constant handled as the file needs
  // Both candidates of --static-weight (firmware unit, as `cubics`; the temperature one only
  // when computed), the weighting each axis's exported cubic has, and --static-weight auto's
  // comparison (nullopt: not auto, or no band; then weight_reason says why).
  std::vector<TemperatureCubic> cubics_time, cubics_temperature;
  std::vector<std::string> weights;
  std::vector<std::optional<StaticWeightChoice>> weight_choices;
  std::string weight_reason;
  std::vector<double> cost_rms;          // projection cost on the run, firmware unit
  // RMS over the range of cubic - full model at state 0 (steady) and along the run's warm-up
  // state (warm-up), firmware unit: what the exported cubic loses in each condition.
  std::vector<double> steady_rms, warm_up_rms;
  // Expected next-run error of each axis's cubic (model band + projection), per condition.
  std::vector<std::optional<CubicExpectedError>> expected;
  std::string band_reason;  // why `expected` is missing (a model without a band)
  double temp_min_c = 0.0, temp_max_c = 0.0;
  // --validation: per axis RMS of the residual block means on the validation run, firmware unit.
  struct Validation {
    std::string reason;  // non-empty: not validated
    std::size_t rows = 0;
    double temp_min_c = 0.0, temp_max_c = 0.0;
    std::vector<double> raw, cubic, full_model;
  };
  std::optional<Validation> validation;
  int runs_combined = 1;  // -i logs whose cubics were averaged
};

// The parameter file's text (PX4 or ArduPilot, every sensor, disabled slots included).
Result<std::string> WriteFile(const CalibrateArgs& a, const std::vector<Sensor>& all);
// Each calibrated sensor's model file to --models (nothing without it).
Status WriteModels(const CalibrateArgs& a, const std::vector<Sensor>& all);
// The console table: span, model, expected error, validation per sensor.
void PrintTable(const std::vector<Sensor>& all);
// One sensor's entry of --json.
nlohmann::json SensorJson(const CalibrateArgs& a, const Sensor& s);
// The gyro cubics for the report's chart (deg/s).
std::vector<CalibrateCurve> CubicCurves(const std::vector<Sensor>& all);

}  // namespace gyrocomp::cli::calibrate
