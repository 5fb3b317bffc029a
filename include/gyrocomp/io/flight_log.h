// Flight-controller logs as gyro logs: PX4 ULog (gyrocomp/io/ulog.h) and ArduPilot DataFlash
// (gyrocomp/io/dataflash.h), recognised by their magic bytes, turned into the same Table a CSV
// gives, so they go through the same GyroLog checks (gyrocomp/io/gyro_log.h).
//
// The table of a flight log has the columns
//     time_s   timestamp of the row, s (ULog 'timestamp', DataFlash TimeUS, divided by 1e6)
//     x_rad_s, y_rad_s, z_rad_s   the gyro rates as logged, rad/s
//     temp_c   the gyro temperature, deg C (absent for ULog sensor_combined)
// One gyro instance is taken: ULog sensor_gyro multi_id N / DataFlash IMU instance N (old logs:
// IMU, IMU2, IMU3 = 0, 1, 2). With several instances and no choice, the reader refuses and lists
// them. A ULog without sensor_gyro data falls back to sensor_combined (no temperature: a warning).
// Frames and compensation (docs/explanation/flight-controller-export.md cites the firmware lines):
// - PX4 sensor_gyro is the driver's output, before the sensors module applies TC_G* and CAL_GYRO*
//   (calibration::Gyroscope::Correct): raw, in the sensor frame, whatever TC_G_ENABLE says. Only
//   sensor_combined (corrected) with TC_G_ENABLE = 1 draws a warning.
// - ArduPilot IMU rows are in the board frame, after the thermal correction (INS_TCALn_ENABLE =
//   1) and the offsets. The reader brings them back to the sensor frame (DataFlashImuToSensorFrame:
//   AHRS_ORIENTATION undone, the log's own INS_TCALn_* correction added back), the one place
//   gyrocomp handles board rotation; what remains is the sensor's curve minus constant offsets.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/io/dataflash.h"
#include "gyrocomp/io/gyro_log.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/io/ulog.h"

namespace gyrocomp {

// Format of a log file; kRosBag: gyrocomp/io/bag_log.h.
enum class LogFormat { kCsv, kULog, kDataFlash, kRosBag };
std::string_view LogFormatName(LogFormat format);  // "csv", "ulog", "dataflash", "rosbag"

// The format of `path` from its first bytes (not its name). "-" (stdin), anything that is not a
// regular file (a pipe: its bytes cannot be read twice), gzip and anything that is not ULog or
// DataFlash is kCsv (ReadCsv then says what is wrong with it). A file that
// cannot be opened is kCsv too: the reader reports it.
LogFormat DetectLogFormat(const std::string& path);

// Column names of a flight-log table.
inline constexpr const char* kFlightTimeCol = "time_s";
// x, y, z angular rate, rad/s, sensor frame.
inline constexpr const char* kFlightRateCols[3] = {"x_rad_s", "y_rad_s", "z_rad_s"};
inline constexpr const char* kFlightTempCol = "temp_c";  // deg C; absent when the log has no temperature

// One gyro instance of a flight log as a table, with where it came from.
struct FlightLogTable {
  Table table;  // time_s, the rate columns and temp_c
  LogFormat format = LogFormat::kULog;  // kULog or kDataFlash
  std::string origin;                     // "ULog sensor_gyro multi_id 0", "DataFlash IMU I=1"
  int instance = 0;  // ULog multi_id or DataFlash IMU instance
  std::optional<std::uint32_t> device_id; // ULog sensor_gyro.device_id
  std::vector<std::string> warnings;      // reader warnings + compensation warnings
  std::vector<LogDamage> damage;          // byte ranges the reader skipped (log_damage.h)
};

// Picks the instance (`instance`: nullopt = the only one) and builds the table. Errors name the
// file and list the instances when the choice is missing or wrong (kInvalidInput).
Result<FlightLogTable> FlightLogFromULog(const ULogContents& log, std::optional<int> instance);
// The same for a DataFlash log.
Result<FlightLogTable> FlightLogFromDataFlash(const DataFlashContents& log, std::optional<int> instance);

// One DataFlash IMU instance (gyro and accel) in the sensor frame, as ArduPilot's
// Tools/scripts/tempcal_IMU.py prepares it: the board rotation AHRS_ORIENTATION undone
// (sensor = R^T board; every fixed rotation of rotations.h), then, with INS_TCAL{n}_ENABLE = 1,
// correct_sensor's correction added back with the log's own coefficients (v += p(T - 35) -
// p(Tcal - 35), T and Tcal = INS_GYR{n}_CALTEMP / INS_ACC{n}_CALTEMP clamped to [TMIN, TMAX]; the
// accel divided by INS_ACC{n}SCAL first, since the firmware scales after correcting). What it did
// is appended to `notes`. Errors: a custom or unknown AHRS_ORIENTATION, an ENABLE other than 0/1/2.
Result<DataFlashImuSeries> DataFlashImuToSensorFrame(const DataFlashContents& log, const DataFlashImuSeries& imu,
                                                     std::vector<std::string>* notes);

// ReadULog / ReadDataFlash by DetectLogFormat, then the above. kCsv -> kInvalidArgument.
// `strict`: a damaged record is an error (ULogReadOptions::strict, DataFlashReadOptions::strict)
// instead of skipped and listed in FlightLogTable::damage.
Result<FlightLogTable> ReadFlightLog(const std::string& path, std::optional<int> instance, bool strict = false);

// Any supported log read into a Table, with the LogSpec adjusted to it. For a CSV: ReadCsv and
// `spec` unchanged. For a flight log: time_col / temp_col become time_s / temp_c, the rate
// columns x_rad_s, y_rad_s, z_rad_s unless `spec` names others than the default "rate_dps", the
// unit rad/s; the warnings are passed to spec.on_warning; temp_required without a temperature
// column is an error saying which topic has none.
struct LogTableRead {
  Table table;  // the log's columns
  LogSpec spec;  // `spec` adjusted to the table
  LogFormat format = LogFormat::kCsv;  // detected format
  std::optional<FlightLogTable> flight;  // without its table (moved to `table`)
};
// `strict`: as for ReadFlightLog (the damage skipped otherwise is in `flight->damage`).
Result<LogTableRead> ReadLogTable(const std::string& path, const LogSpec& spec, bool strict = false);

// Copies origin, device id and warnings of a flight log into `log` (no-op for CSV).
void AttachFlightLogInfo(const LogTableRead& read, GyroLog* log);

}  // namespace gyrocomp
