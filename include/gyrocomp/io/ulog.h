// PX4 ULog: a compact reader (gyro topics, parameters, structure) and a writer of sensor_gyro.
//
// Format: "ULog File Format", PX4 User Guide, https://docs.px4.io/main/en/dev_log/ulog_file_format
// (reference parser: PX4/pyulog, pyulog/core.py). All integers little-endian:
//   header (16 bytes): magic 55 4C 6F 67 01 12 35, uint8 version, uint64 start timestamp (us);
//   then messages: uint16 msg_size (payload bytes), uint8 msg_type, payload.
//   Definitions: 'B' flag bits (first message; incompat bit 0 = data appended at up to three
//   offsets), 'F' format "name:type field;...", 'I' info, 'M' multi info, 'P' parameter,
//   'Q' default parameter. Data: 'A' subscription (uint8 multi_id, uint16 msg_id, name),
//   'R' unsubscription, 'D' data (uint16 msg_id + packed fields, trailing _padding may be
//   omitted), 'L' / 'C' log strings, 'S' sync, 'O' dropout (uint16 ms).
//
// Strictness: every length is checked against the message and the file. A message that does not
// fit in what is left of its segment (the file, or up to the next appended-data offset), with no
// valid message after it, is a truncated last record: dropped, with a warning giving its offset,
// as pyulog does. A bad header (magic, unknown incompat flag) is an error naming the byte offset.
// Any other malformed message (a format that does not parse, data for an unknown subscription, a
// data size outside the format's) is skipped up to the next valid message (ULogReadOptions::
// strict; spec "Synchronization message": readers resynchronise on damaged data), or with
// `strict` an error naming the byte offset. Unknown message types are skipped (the spec asks
// readers to) when a valid message follows them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/io/log_damage.h"

namespace gyrocomp {

// One 'A' subscription: a topic instance and how many 'D' rows it has.
struct ULogTopic {
  std::string name;  // topic name, e.g. "sensor_gyro"
  int multi_id = 0;  // instance of the topic (0 for the first)
  int msg_id = 0;  // subscription's msg id, as the 'D' rows cite it
  std::size_t rows = 0;  // number of 'D' rows read for this subscription
};

// The gyro rows of one subscription of sensor_gyro (x, y, z in rad/s, temperature in deg C,
// device_id) or sensor_combined (gyro_rad[0..2]; no temperature, no device id). Values as logged
// (float32 widened to double, so they compare exactly with pyulog's extracts).
struct ULogGyroSeries {
  std::string topic;  // "sensor_gyro" or "sensor_combined"
  int multi_id = 0;  // instance of the topic (PX4's gyro instance)
  std::vector<std::uint64_t> timestamp_us;  // field 'timestamp'
  std::vector<double> x_rad_s;  // rad/s, sensor frame
  std::vector<double> y_rad_s;  // rad/s
  std::vector<double> z_rad_s;  // rad/s
  std::vector<double> temperature_c;  // empty for sensor_combined
  // sensor_gyro.device_id of the first row (PX4's TC_G{i}_ID); a change of device id inside the
  // series is a warning.
  std::optional<std::uint32_t> device_id;
};

// sensor_accel (x, y, z: specific force, m/s^2, sensor frame, before PX4's calibration) and
// sensor_baro (pressure in Pa as current PX4 logs it, temperature) subscriptions with rows.
struct ULogAccelSeries {
  int multi_id = 0;  // instance of sensor_accel
  std::vector<std::uint64_t> timestamp_us;  // field 'timestamp'
  std::vector<double> x_m_s2;  // m/s^2
  std::vector<double> y_m_s2;  // m/s^2
  std::vector<double> z_m_s2;  // m/s^2
  std::vector<double> temperature_c;  // deg C
  std::optional<std::uint32_t> device_id;  // first row's
};
// A sensor_baro subscription with rows.
struct ULogBaroSeries {
  int multi_id = 0;  // instance of sensor_baro
  std::vector<std::uint64_t> timestamp_us;  // field 'timestamp'
  std::vector<double> pressure_pa;  // Pa
  std::vector<double> temperature_c;  // deg C
  std::optional<std::uint32_t> device_id;  // first row's
};

// The rows of a low-rate vehicle-state topic that gyrocomp reads (vehicle_state.h): one field of
// actuator_armed ('armed', msg/ActuatorArmed.msg), vehicle_status ('arming_state',
// msg/VehicleStatus.msg) or vehicle_land_detected ('landed', msg/VehicleLandDetected.msg), as
// logged (bool / uint8 widened to int). Only the first row and the rows where the value changes
// are kept: the state holds from a row until the next. Never averaged (ULogReadOptions).
struct ULogStateSeries {
  std::string topic;  // "actuator_armed" | "vehicle_status" | "vehicle_land_detected"
  std::string field;  // "armed" | "arming_state" | "landed"
  int multi_id = 0;  // instance of the topic
  std::vector<std::uint64_t> timestamp_us;  // field 'timestamp' of the kept rows
  std::vector<int> value;  // the field's value at those rows
};

// One dropout ('O') message: the logger lost data for duration_ms.
struct ULogDropout {
  std::size_t offset = 0;       // byte offset of the 'O' message
  std::uint16_t duration_ms = 0;  // lost time, ms
};

// What ReadULog found.
struct ULogContents {
  std::string source;  // the path (or the name given to ParseULog), for messages
  int version = 0;  // file format version from the header
  std::uint64_t start_timestamp_us = 0;  // header timestamp, us
  std::vector<std::uint64_t> appended_offsets;  // from the 'B' message, zeros dropped
  std::vector<ULogTopic> topics;                // in subscription order
  // Parameters: the initial value ('P' in the definitions), overwritten by later changes ('P' in
  // the data section). int32 parameters widened to double.
  std::map<std::string, double> parameters;
  std::map<std::string, std::string> info;  // 'I' string values (sys_name, ver_hw, ...)
  std::vector<ULogDropout> dropouts;  // every 'O' message, in file order
  std::vector<ULogGyroSeries> gyros;     // every sensor_gyro subscription with rows
  std::vector<ULogGyroSeries> combined;  // every sensor_combined subscription with rows
  std::vector<ULogAccelSeries> accels;   // every sensor_accel subscription with rows
  std::vector<ULogBaroSeries> baros;     // every sensor_baro subscription with rows
  std::vector<ULogStateSeries> states;   // actuator_armed / vehicle_status / vehicle_land_detected with rows
  std::size_t num_messages = 0;  // messages read, of every type
  std::vector<std::string> warnings;  // truncated last record(s), device-id changes, damage (one line)
  // Byte ranges skipped in recovery (ULogReadOptions::strict false), in file order.
  std::vector<LogDamage> damage;
  // One line for logs: source, version, message count, subscriptions, dropouts.
  std::string BriefReport() const;
};

// How the sensor series are kept (memory: a 1 h, 1 kHz, 3-IMU log in well under 1 GB).
struct ULogReadOptions {
  // > 0: every sensor series (sensor_gyro / combined / accel / baro) is kept as the means of its
  // rows in consecutive windows of this many microseconds of 'timestamp' (window k: timestamps
  // in [k w, (k + 1) w)), timestamp included: one row per window with data. 0: every row as
  // logged (the default).
  std::uint64_t average_window_us = 0;
  // Memory (a gyro command reads one gyro of a 1 GB log): false drops the rows of
  // sensor_accel and sensor_baro (their subscriptions are still listed in `topics`, the series
  // are absent as for a subscription without rows); `gyro_instance` set keeps, of the other
  // sensor_gyro / sensor_combined instances, the timestamps only (their row counts and device
  // ids stay right for messages; x, y, z and temperature are empty).
  bool keep_accel_baro = true;
  std::optional<int> gyro_instance;  // see keep_accel_baro
  // false (the default): a damaged record (a data message for no subscription or of the wrong
  // size, a size running past the data into valid records, an unknown type followed by no valid
  // message, a malformed definition) is skipped up to the next valid record (log_damage.h), the
  // rows of every intact record are kept, and ULogContents::damage lists what was skipped.
  // true: the first damaged record is an error naming its byte offset.
  bool strict = false;
  // Always true: every combination of the options is valid.
  bool IsValid(std::string* error) const { (void)error; return true; }
};

// Reads a whole ULog file (errors: cannot open -> kIo; malformed -> kInvalidInput,
// "<file>: byte <offset>: <what>"). A regular file is memory-mapped and the parsed part given
// back as the parser moves on, so the file is never held whole.
Result<ULogContents> ReadULog(const std::string& path, const ULogReadOptions& options = {});

// The same on bytes in memory (`source` names them in messages); for tests and fuzzing.
Result<ULogContents> ParseULog(const std::uint8_t* data, std::size_t size, const std::string& source,
                               const ULogReadOptions& options = {});

// True when the first bytes are the ULog magic (at least 7 bytes needed).
bool HasULogMagic(const std::uint8_t* data, std::size_t size);

// A sensor_gyro series to write as a ULog (one subscription, multi_id 0).
struct ULogGyroWriteInput {
  std::vector<std::uint64_t> timestamp_us;  // strictly increasing
  std::vector<float> x_rad_s;  // same length as timestamp_us
  std::vector<float> y_rad_s;  // same length as timestamp_us
  std::vector<float> z_rad_s;  // same length as timestamp_us
  std::vector<float> temperature_c;  // same length as timestamp_us
  std::uint32_t device_id = 0;  // written in every row's device_id
  std::string sys_name = "gyrocomp";  // 'I' char[] sys_name
  // Parameters written as 'P' int32 entries (e.g. TC_G_ENABLE = 0).
  std::map<std::string, std::int32_t> int_parameters = {{"TC_G_ENABLE", 0}};
};

// The bytes of a version-1 ULog holding `input` as sensor_gyro (fields of PX4's sensor_gyro
// message: timestamp, timestamp_sample, device_id, x, y, z, temperature, error_count). Errors:
// lengths differ, time not increasing (kInvalidArgument).
Result<std::string> EncodeULogGyro(const ULogGyroWriteInput& input);

// Several sensor topics in one ULog (simulated multi-IMU boards): each series is one subscription
// of sensor_gyro (x, y, z rad/s), sensor_accel (x, y, z m/s^2) or sensor_baro (x = pressure, Pa),
// with PX4's field names (msg/SensorGyro.msg, SensorAccel.msg, SensorBaro.msg: timestamp,
// timestamp_sample, device_id, x, y, z | pressure, temperature, error_count) so pyulog and PX4's
// process_sensor_caldata.py read it. Rows of all series are written in time order.
struct ULogSensorWriteSeries {
  std::string topic;  // "sensor_gyro" | "sensor_accel" | "sensor_baro"
  int multi_id = 0;  // instance of the topic
  std::uint32_t device_id = 0;  // written in every row's device_id
  std::vector<std::uint64_t> timestamp_us;  // strictly increasing
  std::vector<float> x;  // gyro rad/s, accel m/s^2, baro pressure in Pa
  std::vector<float> y;  // baro: empty
  std::vector<float> z;  // baro: empty
  std::vector<float> temperature_c;  // deg C, same length as timestamp_us
};
// A vehicle-state topic to write (simulated flights): one subscription of actuator_armed,
// vehicle_status or vehicle_land_detected with PX4's field layout (the fields of the .msg files
// in their order; the one ULogStateSeries names is set, the others 0).
struct ULogStateWriteSeries {
  std::string topic;  // "actuator_armed" | "vehicle_status" | "vehicle_land_detected"
  std::vector<std::uint64_t> timestamp_us;  // strictly increasing
  std::vector<std::uint8_t> value;  // armed (0/1) | arming_state (1 disarmed, 2 armed) | landed (0/1)
};
// Input of EncodeULog: the series and the 'I' / 'P' entries of the file.
struct ULogWriteInput {
  std::string sys_name = "gyrocomp";  // 'I' char[] sys_name
  std::map<std::string, std::int32_t> int_parameters;  // written as 'P' int32 entries
  std::map<std::string, float> float_parameters;  // written as 'P' float entries
  std::vector<ULogSensorWriteSeries> series;  // in any order; one subscription each
  std::vector<ULogStateWriteSeries> states;  // vehicle-state topics; one subscription each
};
// The bytes of a version-1 ULog holding `input`. Errors (kInvalidArgument): a series' lengths
// differ or its time is not increasing, a name is too long.
Result<std::string> EncodeULog(const ULogWriteInput& input);

// PX4's device id (src/drivers/device/Device.hpp, union DeviceStructure: bus_type 3 bits, bus 5
// bits, address 8 bits, devtype 8 bits, low to high). Bus types (DeviceBusType): 1 I2C, 2 SPI,
// 3 UAVCAN, 4 simulation. devtype: drv_sensor.h (0x3C ICM20689, 0x38 ICM20602, 0x42 BMI055
// gyro, 0x41 BMI055 accel, 0x3D MS5611).
constexpr std::uint32_t Px4DeviceId(std::uint32_t bus_type, std::uint32_t bus, std::uint32_t address,
                                    std::uint32_t devtype) {
  return (bus_type & 0x7u) | ((bus & 0x1Fu) << 3) | ((address & 0xFFu) << 8) | ((devtype & 0xFFu) << 16);
}

}  // namespace gyrocomp
