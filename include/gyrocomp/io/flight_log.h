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
// Rates that may already be compensated are a warning (PX4 TC_G_ENABLE = 1; ArduPilot always:
// its IMU rates are offset-corrected and rotated to the board frame, and INS_TCALn_ENABLE = 1
// adds thermal compensation).
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

enum class LogFormat { kCsv, kULog, kDataFlash, kRosBag };  // kRosBag: gyrocomp/io/bag_log.h (issue 25)
std::string_view LogFormatName(LogFormat format);  // "csv", "ulog", "dataflash", "rosbag"

// The format of `path` from its first bytes (not its name). "-" (stdin), anything that is not a
// regular file (a pipe: its bytes cannot be read twice), gzip and anything that is not ULog or
// DataFlash is kCsv (ReadCsv then says what is wrong with it). A file that
// cannot be opened is kCsv too: the reader reports it.
LogFormat DetectLogFormat(const std::string& path);

// Column names of a flight-log table.
inline constexpr const char* kFlightTimeCol = "time_s";
inline constexpr const char* kFlightRateCols[3] = {"x_rad_s", "y_rad_s", "z_rad_s"};
inline constexpr const char* kFlightTempCol = "temp_c";

// One gyro instance of a flight log as a table, with where it came from.
struct FlightLogTable {
  Table table;
  LogFormat format = LogFormat::kULog;
  std::string origin;                     // "ULog sensor_gyro multi_id 0", "DataFlash IMU I=1"
  int instance = 0;
  std::optional<std::uint32_t> device_id; // ULog sensor_gyro.device_id
  std::vector<std::string> warnings;      // reader warnings + compensation warnings
};

// Picks the instance (`instance`: nullopt = the only one) and builds the table. Errors name the
// file and list the instances when the choice is missing or wrong (kInvalidInput).
Result<FlightLogTable> FlightLogFromULog(const ULogContents& log, std::optional<int> instance);
Result<FlightLogTable> FlightLogFromDataFlash(const DataFlashContents& log, std::optional<int> instance);

// ReadULog / ReadDataFlash by DetectLogFormat, then the above. kCsv -> kInvalidArgument.
Result<FlightLogTable> ReadFlightLog(const std::string& path, std::optional<int> instance);

// Any supported log read into a Table, with the LogSpec adjusted to it. For a CSV: ReadCsv and
// `spec` unchanged. For a flight log: time_col / temp_col become time_s / temp_c, the rate
// columns x_rad_s, y_rad_s, z_rad_s unless `spec` names others than the default "rate_dps", the
// unit rad/s; the warnings are passed to spec.on_warning; temp_required without a temperature
// column is an error saying which topic has none.
struct LogTableRead {
  Table table;
  LogSpec spec;
  LogFormat format = LogFormat::kCsv;
  std::optional<FlightLogTable> flight;  // without its table (moved to `table`)
};
Result<LogTableRead> ReadLogTable(const std::string& path, const LogSpec& spec);

// Copies origin, device id and warnings of a flight log into `log` (no-op for CSV).
void AttachFlightLogInfo(const LogTableRead& read, GyroLog* log);

}  // namespace gyrocomp
