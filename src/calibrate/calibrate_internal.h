// Shared by the calibrate stage's files (not installed).
#pragma once

#include <map>
#include <utility>
#include <string>
#include <vector>

#include "gyrocomp/calibrate/calibrate.h"
#include "gyrocomp/calibrate/still.h"
#include "gyrocomp/core/status.h"
#include "gyrocomp/export/thermal_cubic.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/vehicle_state.h"

namespace gyrocomp::calibrate_internal {

using Sensor = CalibratedSensor;

// The options with the logs they apply to: input = inputs[0], the primary run.
struct Args : CalibrateOptions {
  std::string input;
  std::vector<std::string> inputs;
  std::vector<std::string>* notes = nullptr;  // the readers' notes, once each
};

// ---- calibrate.cc -----------------------------------------------------------------------------
// What a log says besides its sensors: its armed / landed state and its parameters.
struct LogInfo {
  VehicleStateLog state;
  std::map<std::string, double> parameters;  // ULog 'P' / DataFlash PARM (last value)
};
// A log's sensors (gyro, accel, baro per instance) as rows at fit_rate_hz, firmware units;
// `info` (when given) gets the log's state and parameters.
Result<std::vector<Sensor>> SensorsOfULog(const std::string& path, double fit_rate_hz, LogInfo* info = nullptr);
Result<std::vector<Sensor>> SensorsOfDataFlash(const std::string& path, double fit_rate_hz,
                                               std::vector<std::string>* notes_out, LogInfo* info = nullptr);
// The sensor of `run` that is `s` (by device id, else kind and instance); nullptr when none.
const Sensor* Match(const std::vector<Sensor>& run, const Sensor& s);
// Why the firmware has no place for `s` ("" when it has one): slots, ArduPilot's barometer.
std::string SlotReason(const Sensor& s, const Args& a);
// The exported cubic in the firmware's unit, constant as the file needs it.
TemperatureCubic Firmware(const Sensor& s, const Args& a, const TemperatureCubic& model_unit);

// RMS over 201 temperatures of the range of cubic - model at state 0 (first) and at the warm-up
// state `warm` (second), model unit; a temperature-only model: both at state 0.
std::pair<double, double> ConditionErrors(const DriftModel& m, const TemperatureCubic& c, const StateByTemperature& warm);
// A pooled axis's exported cubic for a.optimise_for: the steady cubic c, or the curve with its
// thermal term (rate_gain, or s.temp_lag_s's lag) at s.heating_state projected (pooled_export.cc);
// `model` gets the curve with its term when there is one.
TemperatureCubic ForCondition(const Sensor& s, const Args& a, const TemperatureCubic& c, double rate_gain, DriftModel* model);
// ---- calibrate_runs.cc ------------------------------------------------------------------------
// One input log: its sensors (rows at fit_rate_hz), where the vehicle was still, and per sensor
// and row the still segment the row lies in (-1: not still).
struct Run {
  std::string path;
  std::vector<Sensor> sensors;
  StillDetection detection;
  std::vector<std::vector<int>> segment;  // [sensor][row]
  // [sensor][lag][row]: the temperature low-passed with CalibrateOptions::pooled_lags_s[lag]
  // over the whole log, at the fit's rows (empty for a log read whole, still throughout)
  std::vector<std::vector<std::vector<double>>> lagged_c;
  std::vector<double> row_s;  // [sensor] seconds of log per fit row (1 / fit_rate_hz unless the log is slower)
  std::vector<std::size_t> whole_rows;  // [sensor] fit rows of the whole log, still or not
  LogInfo info;  // the log's state and parameters
};
// Differences between the logs that do not change the fit but that a user should know of: a
// board rotation parameter, or a sensor's log rate (more than 5 %) that differs from the first
// log's, one note per parameter / pair of rates, naming both files and both values
// (CalibrateResult::notes).
std::vector<std::string> DifferencesBetweenLogs(const std::vector<Run>& runs);

// Reads one log: its sensors at still_rate_hz, the still detector on them, then the fit's rows.
// `keep_whole`: a log still throughout is read again at fit_rate_hz.
Result<Run> ReadRun(const std::string& path, LogFormat format, const Args& a, bool keep_whole);
// What the still rows of every run identify for `s` (a sensor of runs[0]).
Sensor::Identification IdentifyRuns(const Sensor& s, const std::vector<Run>& runs, const Args& a);
// The pooled fit of `s` over every run's still rows; sets `reason` when they identify no curve.
void CalibratePooled(Sensor* s, const std::vector<Run>& runs, const Args& a);

// ---- parameter_text.cc ------------------------------------------------------------------------
// The parameter file's text (PX4 or ArduPilot, every sensor, disabled slots included).
Result<std::string> ParameterText(const Args& a, const std::vector<Sensor>& all);

}  // namespace gyrocomp::calibrate_internal
