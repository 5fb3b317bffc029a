// Thermal calibration of every gyro, accelerometer (and PX4 barometer) of a flight log, written
// as ONE parameter file the autopilot loads (docs/explanation/flight-controller-export.md; the CLI is `gyrocomp calibrate`).
//
// Per sensor: the rows in the sensor frame (the readers undo ArduPilot's board rotation and
// thermal correction), block means at fit_rate_hz, the library's default FitDriftModel (auto),
// the static curve projected onto the firmware's cubic over the sensor's temperature range, and
// the constant the firmware leaves to its offset calibration removed:
//   PX4 gyro: X0..X3 = the drift itself (TemperatureCompensation subtracts it before CAL_GYRO);
//   PX4 accel / baro: X0 = 0 (process_sensor_caldata.py subtracts the median: gravity and the
//     constant go to CAL_ACC / the baro offset, recalibrated after loading, its step 12);
//   ArduPilot gyro / accel: re-expanded about 35 C, constant dropped (correct_sensor is relative
//     to INS_*_CALTEMP; tempcal_IMU.py drops it too).
// A sensor that cannot be calibrated keeps its entry (its reason set) and its slot is disabled
// in the file.
//
// Every log goes through the still detector (still.h) first, told the log's armed / landed state
// where the log has one (io/vehicle_state.h): only the rows where the vehicle is still feed the
// fit, and the result lists each log's still segments and the parts rejected, with the reasons.
// Between logs, a board rotation parameter or a sensor's log rate that differs is noted, not
// refused: the rows are in the sensor frame (the readers undo AHRS_ORIENTATION per log; PX4 logs
// before any rotation) and the fit sees means over the same seconds whatever the rate.
// One log that is still throughout (a chamber or bench run) is calibrated as above. Otherwise
// (several logs, or a log in which the vehicle moves) each sensor of the first log is matched in
// the others by its device id (PX4; the instance number where a log has none) and ONE pooled
// least-squares cubic is fitted to all the logs' still rows (pooled_fit.h): the thermal curve
// shared, a constant per log for a gyro or barometer (the power-on offset the boot calibration
// removes) and per still segment for an accelerometer (the attitude's share of gravity). A sensor
// whose still rows do not identify a curve (span under min_span_c, still time under min_still_s)
// has no entry, and its identification says why and what log would help.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gyrocomp/calibrate/still.h"
#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/drift/term_admission.h"
#include "gyrocomp/export/cubic_score.h"
#include "gyrocomp/export/static_weight.h"
#include "gyrocomp/export/thermal_cubic.h"

namespace gyrocomp {

// Settings of CalibrateLogs: the firmware, the fit rate, what is skipped, the export choices.
struct CalibrateOptions {
  // The parameter file and the log kind it needs: "px4" (ULog in; QGroundControl TC_* file out)
  // or "ardupilot" (DataFlash in; INS_TCAL* file out). No default a user could rely on: the CLI
  // requires it.
  std::string format = "px4";
  // Rows per second the fit sees: block means of the log's rows, Hz (tempcal_IMU.py: 2 s moving
  // average). The drift is slow; the fit then sees the same rows whatever the log rate.
  double fit_rate_hz = 1.0;
  // Smallest temperature span calibrated, deg C (ArduPilot's TEMP_RANGE_MIN,
  // AP_InertialSensor_tempcal.cpp).
  double min_span_c = 10.0;
  // Fewest rows after the block means; fewer: the sensor is skipped.
  std::size_t min_rows = 60;
  // Still detection on every log (still.h; its defaults: 1 s windows, threshold 3, 2 s margin,
  // segments of 30 s at least), told the log's own state where it has one (io/vehicle_state.h:
  // PX4 actuator_armed, vehicle_status, vehicle_land_detected; ArduPilot ARM and EV): a row is
  // not used when the log says armed, or not landed; before the log's first state message the
  // state is not known and the IMU alone decides.
  StillDetectorOptions still;
  // Rows per second the still detector sees: means of the log's rows over 1 / still_rate_hz, Hz
  // (the statistic compares each window with the quietest ones, so the averaging cancels; a log
  // slower than this is seen at its own rate).
  double still_rate_hz = 50.0;
  // Least still time of a sensor over all the logs, s; less: no parameter entry (the pooled fit
  // of a few still minutes is the noise's, not the drift's). 300 s: e.g. one 5 min warm-up.
  double min_still_s = 300.0;
  // Pooled fit: a shared dT/dt gain fitted with the cubic where the still rows' heating rates
  // spread over 1e-3 C/s (SD), the cubic kept at dT/dt = 0 (pooled_fit.h). False: the cubic alone.
  bool pooled_dtemp = true;
  // Pooled fit: the temperature the curve is a function of may lag the logged one (the MEMS
  // structure behind the die thermometer, a board's stress relaxing behind its heating). Each
  // log's temperature is low-passed (first order, the whole log, flight included) with each lag
  // of pooled_lags_s; the lag whose pooled cubic predicts the held-out groups best is kept when
  // its paired held-out gain over no lag beats its standard error (term_admission.h, Eq. A-4),
  // the lag scored on each group being the one the other groups choose (so the best of the
  // candidates is not tested on the scores that chose it); one lag per sensor (every axis); then
  // no dT/dt term. Empty: no lag searched.
  std::vector<double> pooled_lags_s = {10.0, 20.0, 40.0, 60.0, 90.0, 120.0, 180.0, 240.0};
  // What the exported cubic is optimised for (CubicCondition): "steady" (dT/dt = 0, the static
  // curve), "warm-up" (the state the run had while heating) or "both" (their mean). A single
  // run: the drift model projected at that state. Pooled: the shared curve plus what the thermal
  // term the fit kept adds at the state every log's still rows had while heating
  // (CalibratedSensor::heating_state: the dT/dt gain times the heating rate, or the curve at the
  // lagged temperature T - (T - T_lag)), projected onto the cubic; a sensor with neither term
  // gets the steady curve whatever the condition.
  std::string optimise_for = "steady";
  // How the static curve is estimated: "temperature" (each temperature alike, static_cubic.h),
  // "time" (the fitted model's own curve at state 0) or "auto" (per axis, the one with the lower
  // expected next-run error; static_weight.h).
  std::string static_weight = "auto";
  // A second log of the same board (same kind): every exported cubic (firmware formula) and the
  // full model scored on it. Empty: no validation.
  std::string validation_path;
  // Validation: the residual block means, s (bench/imu_calibration_side_by_side.py).
  double block_s = 10.0;

  // False with a message naming the field when a value is out of range.
  bool IsValid(std::string* error) const;
};

// One sensor instance of a log: its rows (sensor frame, firmware unit) and what calibration made
// of them.
struct CalibratedSensor {
  std::string type;  // gyro | accel | baro
  int instance = 0;  // PX4 multi_id / DataFlash IMU instance
  std::optional<std::uint32_t> device_id;  // PX4 device id (DataFlash logs have none)
  double log_rate_hz = 0.0;  // rows per second as the log has them (before any averaging), Hz; 0: not known
  std::vector<double> time_s;  // s, after the block means
  std::vector<double> temp_c;  // deg C, after the block means
  std::vector<std::vector<double>> values;  // per axis, firmware unit (rad/s, m/s^2, Pa)
  std::vector<std::string> cols;            // x_rad_s | x_m_s2 | pressure_pa
  std::string unit;                         // firmware unit
  double to_model = 1.0;                    // firmware unit -> model unit (gyro: deg/s)
  std::string model_unit;  // unit of the models, e.g. deg/s for a gyro
  // Outcome.
  std::string reason;  // non-empty: skipped, and why
  int slot = -1;       // PX4 slot / ArduPilot IMU n
  std::vector<DriftModel> models;  // one per axis
  std::vector<TemperatureCubic> cubics;  // firmware unit, constant handled as the file needs
  // Both candidates of static_weight (firmware unit, as `cubics`; the temperature one only when
  // computed), the weighting each axis's exported cubic has, and "auto"'s comparison (nullopt:
  // not auto, or no band; then weight_reason says why).
  std::vector<TemperatureCubic> cubics_time;  // the time estimator's cubics (firmware unit)
  std::vector<TemperatureCubic> cubics_temperature;  // the temperature estimator's (empty when not computed)
  std::vector<std::string> weights;  // per axis, the weighting of the exported cubic: "time" | "temperature"
  // Per axis, auto's comparison (nullopt: not auto, or it failed).
  std::vector<std::optional<StaticWeightChoice>> weight_choices;
  std::string weight_reason;  // why auto fell back to "temperature"; "" otherwise
  std::vector<double> cost_rms;  // projection cost on the run, firmware unit
  // RMS over the range of cubic - full model at state 0 (steady) and along the run's warm-up
  // state (warm-up), firmware unit: what the exported cubic loses in each condition.
  std::vector<double> steady_rms;  // per axis, steady condition
  std::vector<double> warm_up_rms;  // per axis, along the warm-up
  // Expected next-run error of each axis's cubic (model band + projection), per condition.
  std::vector<std::optional<CubicExpectedError>> expected;
  std::string band_reason;  // why `expected` is missing (a model without a band)
  double temp_min_c = 0.0;  // lowest temperature calibrated (the cubics' TMIN), deg C
  double temp_max_c = 0.0;  // highest (TMAX), deg C
  // Validation: per axis RMS of the residual block means on the validation run, firmware unit.
  struct Validation {
    std::string reason;  // non-empty: not validated
    std::size_t rows = 0;  // rows of the validation run after the block means
    double temp_min_c = 0.0;  // lowest temperature of the validation run, deg C
    double temp_max_c = 0.0;  // highest, deg C
    std::vector<double> raw;  // per axis, of the uncorrected rows
    std::vector<double> cubic;  // per axis, after the exported cubic (firmware formula)
    std::vector<double> full_model;  // per axis, after the full model
  };
  std::optional<Validation> validation;  // the scores on CalibrateOptions::validation_path, when given
  int runs_combined = 1;  // logs whose still rows were pooled (1: one still-throughout log)
  // "single run" (one log, still throughout: the drift model and projection above) or "pooled"
  // (one least-squares cubic over every log's still rows, a constant per log or segment).
  std::string fit = "single run";
  // Pooled: per axis, 1 sigma of the fitted curve over the range from the fit's covariance
  // (FitPooledCubic's curve_sd), firmware unit; empty for a single run (it has `expected`).
  std::vector<double> curve_sd;
  // Pooled: the lag of the temperature the cubic was fitted on behind the logged one, s (0: the
  // logged temperature; CalibrateOptions::pooled_lags_s).
  double temp_lag_s = 0.0;
  // Pooled: the paired held-out gain of the lag over none (relative: each axis's per-group
  // held-out RMS divided by its mean without the lag, averaged over the axes), each group scored
  // with the lag the other groups choose (CalibrateOptions::pooled_lags_s); pairs 0 when no lag
  // was searched or none predicts better than the logged temperature.
  TermGain lag_term;
  // Pooled: per axis, the shared dT/dt gain fitted with the cubic (PooledCubic::rate_gain),
  // firmware unit per (C/s); 0: no dT/dt term (a lag kept, not identified, or not admitted).
  std::vector<double> rate_gain;
  // Pooled: the thermal state the still rows of every log had while heating, by temperature
  // (HeatingStateByTemperature, the binning of the single run's StateWhileHeating: the median
  // over the rows heating at 1/300 C/s or more, 1 C bins from temp_min_c, 0 where no row heated):
  // dT/dt in C/s where an axis kept the dT/dt term, T - T_lag in C with a lag (temp_lag_s > 0,
  // Eq. TS-2). CalibrateOptions::optimise_for "warm-up" / "both" fit the exported cubic to the
  // curve at this state (gain x state added; the lagged curve at T - state) / to the mean of
  // that and the steady curve. Empty `state` (heating_state_kind ""): no such term, and every
  // condition gives the steady curve.
  StateByTemperature heating_state;
  // The state's name (ThermalStateColumnName): "dtemp_c_per_s", "lag_excess_c", or "" (no term).
  std::string heating_state_kind;
  // The rows the fit saw, for drawing them under the exported cubics (the calibrate report): a
  // single run's block means, or every log's still rows of a pooled fit, constant included.
  struct FitRows {
    std::vector<double> time_s;  // s, the row's time in its log
    std::vector<double> temp_c;  // deg C (the logged temperature, also with a lag kept)
    std::vector<std::vector<double>> values;  // per axis, firmware unit
    std::vector<int> log;  // index into CalibrateResult::inputs
    // The constant the row shares (a single run: 0; pooled: its log for a gyro or barometer, its
    // still segment for an accelerometer, as the pooled fit groups them).
    std::vector<int> group;
  };
  FitRows fit_rows;  // empty when skipped
  // Per axis, the exported cubic's band against temperature, firmware unit: the half-width is
  // z(level) sd. A single run: sd = sqrt((cubic - model)^2 + band_sd^2) of the steady condition
  // (SteadyCubicErrorProfile; its RMS over temp_c is the expected steady error); pooled: sd =
  // curve_sd at every temperature (the fit's 1 sigma of the curve, its RMS over the range).
  // Empty sd: no band (a model without one, band_reason says why).
  struct CurveBand {
    double level = 0.9;  // the band's level (two-sided)
    double z = 0.0;  // z(level)
    std::vector<double> temp_c;  // deg C, over [temp_min_c, temp_max_c]
    std::vector<double> sd;  // firmware unit
  };
  std::vector<CurveBand> curve_bands;  // per axis, when calibrated
  // What the logs identify for a sensor.
  struct Identification {
    double temp_min_c = 0.0;  // lowest still temperature over all logs, deg C
    double temp_max_c = 0.0;  // highest, deg C
    // Temperatures whose change the fit sees: the union of the ranges inside each constant's
    // group (a log for gyro / baro, a still segment for an accelerometer), deg C.
    double identified_span_c = 0.0;
    double overlap_c = 0.0;  // temperatures (0.5 C bins) covered by two or more logs, deg C
    int logs = 0;  // logs with this sensor
    int logs_with_still = 0;  // of them, logs with still rows
    double still_s = 0.0;  // still time used, s
    std::string statement;  // one line: the figures above in words
    std::string would_help;  // one line: which log would help most
  };
  Identification identification;  // what the logs identify for this sensor (every sensor, calibrated or not)

  // True unless the sensor was skipped.
  bool calibrated() const { return reason.empty(); }
};

// What CalibrateLogs did: every sensor, the parameter file, the readers' notes.
struct CalibrateResult {
  std::vector<std::string> inputs;  // the logs, first = primary (models, bands, cost)
  CalibrateOptions options;  // the options used
  std::vector<CalibratedSensor> sensors;  // every sensor of the first log, skipped ones too
  // The parameter file (PX4 or ArduPilot, every sensor, disabled slots included); empty when no
  // sensor could be calibrated.
  std::string parameter_text;
  // What the readers said on the way (e.g. an ArduPilot log's rotation undone), once each.
  std::vector<std::string> notes;
  // Where the vehicle was still in one log.
  struct LogStill {
    std::string path;  // the log
    StillDetection detection;  // segments, rejected parts with reasons, noise levels
    // The log's armed / landed state the detector was given (VehicleStateLog::BriefReport, e.g.
    // "armed: actuator_armed.armed, vehicle_status.arming_state from 1.00 s; landed: ...").
    std::string state;
  };
  // Per log (in the order of `inputs`): where the vehicle was still (StillDetection::still, the
  // per-row flags, cleared to save memory; segments and rejected parts kept).
  std::vector<LogStill> logs;

  // True when at least one sensor was calibrated.
  bool AnyCalibrated() const;
  // The per-sensor table: span, model, projection cost, expected error, static weighting and,
  // with a validation run, its scores; then each sensor's identification and each log's still
  // segments and rejected parts.
  std::string BriefReport() const;
};

// Calibrates every sensor of logs[0], combined with the same board's sensors in logs[1..]. An
// error: options not valid, a log unreadable, logs of different kinds or different boards (no
// device id in common), the format not the logs' kind. A result with no calibrated sensor is not
// an error: each sensor carries its reason and parameter_text is empty.
Result<CalibrateResult> CalibrateLogs(const std::vector<std::string>& logs, const CalibrateOptions& options);

// "steady 1e-4 2e-4 3e-4" (firmware unit, per axis) or the reason no band is available.
std::string ExpectedErrorText(const CalibratedSensor& s, bool warm_up);
// "static weight temperature time time (auto, expected error ...)".
std::string StaticWeightText(const CalibratedSensor& s);

}  // namespace gyrocomp
