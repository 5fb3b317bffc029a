// A gyro log: time, one or more rate axes in deg/s, and (optionally) temperature, taken from a
// Table by column name, with its sampling checked.
//
// Sampling rules (nothing is ever resampled silently):
//   - a time column must be strictly increasing: a repeat or a step backwards is an error naming
//     the line;
//   - irregular sampling (gaps, bursts, jitter beyond SamplingCheck tolerances) is an error whose
//     message gives the statistics (median dt, min/max dt, number of gaps, longest gap) and says
//     to pass --resample HZ, unless LogSpec::resample_hz is set; then the log is linearly
//     interpolated onto a uniform grid and SamplingReport says what was done;
//   - without a time column, LogSpec::fs_hz gives the rate and time is i / fs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gyrocomp/io/bag.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/core/status.h"
#include "gyrocomp/core/units.h"

namespace gyrocomp {

// Which columns of a log are time, rate and temperature, in which unit, and what is refused.
struct LogSpec {
  // Name of the time column (seconds). If absent from the file and fs_hz is set, time is i/fs.
  std::string time_col = "time_s";
  // Rate column(s): one per axis.
  std::vector<std::string> rate_cols = {"rate_dps"};
  // Unit of the rate columns; converted to deg/s on load. For ULog / DataFlash input the unit
  // is the log's own (rad/s): ReadGyroLog sets it.
  RateUnit rate_unit = RateUnit::kDegPerSec;
  // Temperature column (deg C). Required only when temp_required.
  std::string temp_col = "temp_c";
  bool temp_required = false;  // false: a log without temp_col loads with empty temp_c
  // Rate columns are required unless the caller only needs other columns.
  bool rates_required = true;
  // Sample rate when the file has no time column (Hz). If both are given, the time column wins
  // and a mismatch beyond 1% is an error.
  std::optional<double> fs_hz;
  // Resample irregular logs onto this uniform rate (Hz), by linear interpolation.
  std::optional<double> resample_hz;
  // Minimum number of samples the analysis needs; fewer is an error naming the file.
  std::size_t min_samples = 2;
  // Tolerances for calling a log irregular: any interval outside
  // [ (1 - jitter_tolerance) * median_dt, (1 + jitter_tolerance) * median_dt ] counts; the log
  // is irregular if more than max_irregular_fraction of the intervals do, or any interval is a
  // gap (> gap_factor * median_dt).
  double jitter_tolerance = 0.1;
  double max_irregular_fraction = 0.001;  // fraction of irregular intervals above which the log is irregular
  double gap_factor = 1.5;  // an interval > gap_factor * median_dt is a gap
  // Values no instrument produces are refused at load with the file, line and value, so no stage
  // meets a number near the end of the double range: |rate| above max_abs_rate_dps (after the
  // unit conversion; MEMS full scales are <= 1e4 deg/s), a temperature outside
  // [min_temp_c, max_temp_c] (absolute zero .. 1000 C), a sample rate (given or measured from
  // the time column) outside [kMinFsHz, kMaxFsHz].
  double max_abs_rate_dps = 1e6;
  double min_temp_c = -273.15;  // deg C; lowest temperature accepted
  double max_temp_c = 1000.0;  // deg C; highest temperature accepted
  static constexpr double kMinFsHz = 1e-6;  // one sample in ~11.6 days
  static constexpr double kMaxFsHz = 1e9;   // 1 GHz
  // Memory resampling may take, bytes: --resample 1e9 (or a 1e9 s gap) is refused before the
  // allocation with what it would need ("needs N GB ...; at most M GB allowed (--max-memory)").
  std::size_t max_memory_bytes = std::size_t{8} << 30;
  // Flight-controller logs (ULog, DataFlash; gyrocomp/io/flight_log.h): which gyro instance to
  // read. nullopt: the only one; with several, reading fails and lists them. Ignored for CSV.
  std::optional<int> instance;
  // ROS bags (gyrocomp/io/bag.h): the sensor_msgs/Imu topic (nullopt: the only one; with
  // several, reading fails and lists them) and the time of a row (header stamp or receive time).
  std::optional<std::string> topic;
  BagTimeSource bag_time = BagTimeSource::kHeader;  // which stamp is a row's time
  // CSV input read by ReadLogTable: the columns kept in memory besides time_col, rate_cols and
  // temp_col. nullopt (default): every column of the file (for commands whose output is "the
  // input columns plus ..."). A list (may be empty): only those; the cells of the others are
  // still parsed and checked, every bad one the same error as ever, but not stored
  // (CsvReadOptions::columns). ReadGyroLog keeps none. Ignored for the other formats.
  std::optional<std::vector<std::string>> keep_cols;
  // Called with each warning of a flight-log reader as it is found (may be empty: the warnings
  // are also in GyroLog::warnings). The CLI prints them.
  std::function<void(const std::string&)> on_warning;

  // "LogSpec::fs_hz = -1: must be > 0 (Hz)" style message on failure.
  bool IsValid(std::string* error) const;
};

// What the sampling check found, and what (if anything) was done about it.
struct SamplingReport {
  double fs_hz = 0.0;            // rate of the returned (uniform) log
  double median_dt_s = 0.0;  // median sample interval, s
  double min_dt_s = 0.0;  // shortest interval, s
  double max_dt_s = 0.0;  // longest interval, s
  std::size_t num_intervals = 0;  // time intervals checked
  std::size_t num_irregular = 0; // intervals outside the jitter tolerance
  std::size_t num_gaps = 0;      // intervals > gap_factor * median_dt
  double longest_gap_s = 0.0;  // longest gap, s (0 without gaps)
  bool irregular = false;  // more than max_irregular_fraction irregular intervals, or a gap
  bool resampled = false;  // put on a uniform grid (LogSpec::resample_hz)
  std::size_t rows_in = 0;       // rows read
  std::size_t rows_out = 0;      // rows after resampling
  std::size_t rows_in_gaps = 0;  // resampled rows that lie inside a gap (interpolated across it)
  bool time_from_fs = false;     // no time column: time = i / LogSpec::fs_hz
  // One line for logs: the rate, the intervals and what was done about them.
  std::string BriefReport() const;
};

// A loaded gyro record: uniform time, rates in deg/s per axis, temperature.
struct GyroLog {
  std::string source;  // the file path, for messages
  double fs_hz = 0.0;  // sample rate, Hz
  std::vector<double> time_s;  // s, uniform at fs_hz
  std::vector<std::string> axis_names;          // the rate column names, in order
  std::vector<std::vector<double>> rate_dps;    // one vector per axis
  std::vector<double> temp_c;                   // empty when the file has no temperature
  SamplingReport sampling;  // how the time column was checked and what was done
  // Flight-controller logs only (gyrocomp/io/flight_log.h). The gyro's device id as logged in
  // PX4 ULog sensor_gyro.device_id (what PX4's TC_G{i}_ID holds); empty for CSV, DataFlash and
  // ULog sensor_combined, which do not log one.
  std::optional<std::uint32_t> device_id;
  // Where the rows came from in a flight log, e.g. "ULog sensor_gyro multi_id 1" or
  // "DataFlash IMU I=0"; empty for CSV.
  std::string origin;
  // The flight log's gyro instance (ULog multi_id, DataFlash IMU I); empty for CSV.
  std::optional<int> instance;
  // What the flight-log reader warned about (truncated last record, rates that may already be
  // compensated); also passed to LogSpec::on_warning as they happen.
  std::vector<std::string> warnings;
  // Samples per axis.
  std::size_t num_samples() const { return time_s.size(); }
  // True when the log has a temperature column.
  bool has_temperature() const { return !temp_c.empty(); }
};

// Extracts and validates a GyroLog from a table already read by ReadCsv. Errors name the file
// and, for timestamps, the line (header is line 1, first data row is line 2).
Result<GyroLog> LoadGyroLog(const Table& table, const LogSpec& spec);

// LoadGyroLog that moves the columns it takes out of `table` instead of copying them (on success
// they are removed from it; Table::header keeps their names for messages), except a column
// spec.keep_cols names or one that serves two roles. With resampling nothing is moved. For a
// table read only for its log, this halves the memory the log takes to load.
Result<GyroLog> TakeGyroLog(Table* table, const LogSpec& spec);

// ReadLogTable (keeping only the log's columns of a CSV) + TakeGyroLog.
Result<GyroLog> ReadGyroLog(const std::string& path, const LogSpec& spec);

// Sampling statistics of a time vector (seconds, strictly increasing, at least 2 entries; not
// checked here). `spec` supplies the jitter/gap tolerances; rows_in = time_s.size().
SamplingReport MeasureSampling(const std::vector<double>& time_s, const LogSpec& spec);

// Linearly interpolates every column of `table` onto the uniform grid t0 + k / fs_hz
// (k = 0 .. floor((t_end - t0) * fs_hz)), t0 / t_end = first / last time. The time column must
// be strictly increasing (errors as in LoadGyroLog). For commands whose output is "the input
// columns plus ...": they resample the table the same way LoadGyroLog resampled the log, so rows
// line up (same grid, bit for bit).
Result<Table> ResampleTable(const Table& table, const std::string& time_col, double fs_hz);

}  // namespace gyrocomp
