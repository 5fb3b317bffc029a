// What a flight-controller log or a ROS bag holds (`gyrocomp inspect`, `gyrocomp.inspect`): the
// format, every sensor instance (gyro, accel, baro) with rows, device id, time span, mean sample
// rate and temperature range, the damage found, the thermal-compensation parameters, the
// readers' warnings; for a bag, every topic with its type, encoding, messages and mean rate.
//
// Device ids: PX4 ULog sensor_gyro / sensor_accel / sensor_baro device_id as logged (what
// TC_G{i}_ID holds); ArduPilot INS_GYR_ID, INS_GYR2_ID, INS_GYR3_ID (INS_ACC*_ID for accels) for
// IMU instance 0, 1, 2 (AP_InertialSensor::var_info) and BARO{n}_DEVID for baro n-1.
// Compensation parameters: PX4 TC_G_ENABLE / TC_G{i}_ID, ArduPilot INS_TCAL{n}_ENABLE.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "gyrocomp/core/status.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/log_damage.h"

namespace gyrocomp {

// How InspectLog reads a log.
struct InspectOptions {
  // A damaged ULog / DataFlash record or bag record is an error (naming its byte offset) instead of
  // skipped and listed in LogInventory::damage. Default: skipped.
  bool strict = false;
  // Always true (the one option has no invalid value); kept for the Options contract.
  bool IsValid(std::string* error) const;
};

// One sensor instance of a flight log.
struct LogSensorInstance {
  std::string type;    // "gyro", "accel" or "baro"
  std::string source;  // the ULog topic or DataFlash message it was read from
  int instance = 0;    // ULog multi_id, DataFlash instance
  std::size_t rows = 0;  // records
  std::optional<std::uint32_t> device_id;  // as logged (see the top of this file); nullopt: none
  std::optional<double> time_span_s;       // last - first timestamp, s; nullopt: not read (DataFlash baro)
  std::optional<double> sample_rate_hz;    // (rows - 1) / time span, Hz; nullopt: one row or not read
  std::optional<std::pair<double, double>> temp_range_c;  // lowest, highest temperature, deg C; nullopt: none logged
};

// What InspectLog found.
struct LogInventory {
  LogFormat format = LogFormat::kULog;        // ULog, DataFlash or a ROS bag
  std::vector<LogSensorInstance> sensors;     // every sensor instance of a flight log; empty for a bag
  std::vector<LogDamage> damage;              // byte ranges skipped
  std::vector<std::string> warnings;          // what the reader warned about
  // The whole listing as `gyrocomp inspect --json` writes it, without its "input" key: format,
  // sensors, gyro_instances, damage, compensation_parameters, warnings, and per format topics /
  // info / dropouts / appended_segments (ULog), messages (DataFlash) or topics (bag)
  // (docs/reference/cli/inspect.md).
  nlohmann::json listing;
  // "ulog: 3 sensor instances (gyro 2, accel 1), no damage" / "mcap: 4 topics, 1 IMU, 1 damaged range".
  std::string BriefReport() const;
};

// Lists what the ULog, DataFlash log or ROS bag at `path` holds, recognised by its first bytes.
// Errors: kInvalidInput for a file that is none of them (a CSV), or, with options.strict, a damaged
// record; the readers' errors otherwise.
Result<LogInventory> InspectLog(const std::string& path, const InspectOptions& options = {});

}  // namespace gyrocomp
