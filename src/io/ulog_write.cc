// ULog writer of one sensor_gyro series (include/gyrocomp/io/ulog.h), following the message
// layouts of the PX4 "ULog File Format" spec; read back by ReadULog in the tests.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <queue>
#include <string>
#include <tuple>

#include "gyrocomp/io/ulog.h"

namespace gyrocomp {

namespace {

// PX4's sensor_gyro message (msg/SensorGyro.msg), as its logger writes the format.
constexpr const char* kSensorGyroFormat =
    "sensor_gyro:uint64_t timestamp;uint64_t timestamp_sample;uint32_t device_id;float x;float y;float z;"
    "float temperature;uint32_t error_count;";
// msg/SensorAccel.msg and msg/SensorBaro.msg (the fields process_sensor_caldata.py reads:
// device_id, x/y/z or pressure, temperature).
constexpr const char* kSensorAccelFormat =
    "sensor_accel:uint64_t timestamp;uint64_t timestamp_sample;uint32_t device_id;float x;float y;float z;"
    "float temperature;uint32_t error_count;";
constexpr const char* kSensorBaroFormat =
    "sensor_baro:uint64_t timestamp;uint64_t timestamp_sample;uint32_t device_id;float pressure;"
    "float temperature;uint32_t error_count;";

// The vehicle-state topics (msg/ActuatorArmed.msg, msg/VehicleStatus.msg: its first fields,
// msg/VehicleLandDetected.msg), the fields in the order of the .msg files, as the logger writes
// a format; the value of ULogStateWriteSeries goes into `armed`, `arming_state` or `landed`.
constexpr const char* kActuatorArmedFormat =
    "actuator_armed:uint64_t timestamp;bool armed;bool prearmed;bool ready_to_arm;bool lockdown;bool kill;"
    "bool termination;bool in_esc_calibration_mode;uint8_t[1] _padding0;";
constexpr const char* kVehicleStatusFormat =
    "vehicle_status:uint64_t timestamp;uint64_t armed_time;uint64_t takeoff_time;uint8_t arming_state;"
    "uint8_t latest_arming_reason;uint8_t latest_disarming_reason;uint8_t[5] _padding0;";
constexpr const char* kVehicleLandDetectedFormat =
    "vehicle_land_detected:uint64_t timestamp;bool freefall;bool ground_contact;bool maybe_landed;bool landed;"
    "bool in_ground_effect;bool in_descend;bool has_low_throttle;bool vertical_movement;bool horizontal_movement;"
    "bool rotational_movement;bool close_to_ground_or_skipped_check;bool at_rest;uint8_t[4] _padding0;";

void PutU8(std::string* s, std::uint8_t v) { s->push_back(static_cast<char>(v)); }
void PutU16(std::string* s, std::uint16_t v) {
  PutU8(s, static_cast<std::uint8_t>(v & 0xFF));
  PutU8(s, static_cast<std::uint8_t>(v >> 8));
}
void PutU32(std::string* s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) PutU8(s, static_cast<std::uint8_t>((v >> (8 * i)) & 0xFF));
}
void PutU64(std::string* s, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) PutU8(s, static_cast<std::uint8_t>((v >> (8 * i)) & 0xFF));
}
void PutF32(std::string* s, float f) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  PutU32(s, bits);
}

// spec "Message Header": uint16 msg_size (payload), uint8 msg_type, payload.
void PutMessage(std::string* out, char type, const std::string& payload) {
  PutU16(out, static_cast<std::uint16_t>(payload.size()));
  PutU8(out, static_cast<std::uint8_t>(type));
  out->append(payload);
}

void PutHeaderAndInfo(std::string* out, std::uint64_t start_us, const std::string& sys_name) {
  // spec "File Header": magic, version 1, start timestamp.
  out->append("\x55\x4C\x6F\x67\x01\x12\x35", 7);
  PutU8(out, 1);
  PutU64(out, start_us);
  // 'B' flag bits: no compat, no incompat flags, no appended data.
  PutMessage(out, 'B', std::string(40, '\0'));
  // 'I' info: uint8 key_len, "char[len] sys_name", value.
  const std::string key = "char[" + std::to_string(sys_name.size()) + "] sys_name";
  std::string p;
  PutU8(&p, static_cast<std::uint8_t>(key.size()));
  p += key + sys_name;
  PutMessage(out, 'I', p);
}

Status CheckSeries(const ULogSensorWriteSeries& s) {
  const std::string what = "ULogSensorWriteSeries " + s.topic + " multi_id " + std::to_string(s.multi_id);
  if (s.topic != "sensor_gyro" && s.topic != "sensor_accel" && s.topic != "sensor_baro")
    return InvalidArgument(what + ": topic must be sensor_gyro, sensor_accel or sensor_baro");
  const std::size_t n = s.timestamp_us.size();
  const bool baro = s.topic == "sensor_baro";
  if (s.x.size() != n || s.temperature_c.size() != n || (!baro && (s.y.size() != n || s.z.size() != n)))
    return InvalidArgument(what + ": values and temperature need one entry per timestamp (" + std::to_string(n) + ")");
  for (std::size_t i = 1; i < n; ++i)
    if (s.timestamp_us[i] <= s.timestamp_us[i - 1]) return InvalidArgument(what + ": timestamp_us not increasing at row " + std::to_string(i));
  if (s.multi_id < 0 || s.multi_id > 255) return InvalidArgument(what + ": multi_id must be 0..255");
  return Status::Ok();
}

std::string DataRow(const ULogSensorWriteSeries& s, std::uint16_t msg_id, std::size_t i) {
  std::string row;
  PutU16(&row, msg_id);
  PutU64(&row, s.timestamp_us[i]);  // timestamp
  PutU64(&row, s.timestamp_us[i]);  // timestamp_sample
  PutU32(&row, s.device_id);
  PutF32(&row, s.x[i]);
  if (s.topic != "sensor_baro") {
    PutF32(&row, s.y[i]);
    PutF32(&row, s.z[i]);
  }
  PutF32(&row, s.temperature_c[i]);
  PutU32(&row, 0);  // error_count
  return row;
}

Status CheckState(const ULogStateWriteSeries& s) {
  const std::string what = "ULogStateWriteSeries " + s.topic;
  if (s.topic != "actuator_armed" && s.topic != "vehicle_status" && s.topic != "vehicle_land_detected")
    return InvalidArgument(what + ": topic must be actuator_armed, vehicle_status or vehicle_land_detected");
  if (s.value.size() != s.timestamp_us.size()) return InvalidArgument(what + ": one value per timestamp");
  for (std::size_t i = 1; i < s.timestamp_us.size(); ++i)
    if (s.timestamp_us[i] <= s.timestamp_us[i - 1]) return InvalidArgument(what + ": timestamp_us not increasing at row " + std::to_string(i));
  return Status::Ok();
}

// One row of a state topic in the layout of its format above.
std::string StateRow(const ULogStateWriteSeries& s, std::uint16_t msg_id, std::size_t i) {
  std::string row;
  PutU16(&row, msg_id);
  PutU64(&row, s.timestamp_us[i]);
  if (s.topic == "actuator_armed") {
    PutU8(&row, s.value[i]);
    row.append(7, '\0');  // prearmed .. _padding0
  } else if (s.topic == "vehicle_status") {
    PutU64(&row, 0), PutU64(&row, 0);  // armed_time, takeoff_time
    PutU8(&row, s.value[i]);
    row.append(7, '\0');  // reasons, _padding0
  } else {
    row.append(3, '\0');  // freefall, ground_contact, maybe_landed
    PutU8(&row, s.value[i]);
    row.append(12, '\0');  // in_ground_effect .. at_rest, _padding0
  }
  return row;
}

}  // namespace

Result<std::string> EncodeULog(const ULogWriteInput& in) {
  for (const auto& s : in.series)
    if (Status st = CheckSeries(s); !st.ok()) return st.error();
  for (const auto& s : in.states)
    if (Status st = CheckState(s); !st.ok()) return st.error();
  if (in.sys_name.size() > 200) return InvalidArgument("ULogWriteInput: sys_name longer than 200 characters");
  std::uint64_t start = 0;
  bool any = false;
  for (const auto& s : in.series)
    if (!s.timestamp_us.empty()) start = any ? std::min(start, s.timestamp_us.front()) : s.timestamp_us.front(), any = true;
  std::string out;
  PutHeaderAndInfo(&out, start, in.sys_name);
  for (const char* f : {kSensorGyroFormat, kSensorAccelFormat, kSensorBaroFormat}) PutMessage(&out, 'F', f);
  if (!in.states.empty())
    for (const char* f : {kActuatorArmedFormat, kVehicleStatusFormat, kVehicleLandDetectedFormat}) PutMessage(&out, 'F', f);
  for (const auto& [name, value] : in.int_parameters) {
    const std::string key = "int32_t " + name;
    if (key.size() > 255) return InvalidArgument("ULogWriteInput: parameter name too long: " + name);
    std::string p;
    PutU8(&p, static_cast<std::uint8_t>(key.size()));
    p += key;
    PutU32(&p, static_cast<std::uint32_t>(value));
    PutMessage(&out, 'P', p);
  }
  for (const auto& [name, value] : in.float_parameters) {
    const std::string key = "float " + name;
    if (key.size() > 255) return InvalidArgument("ULogWriteInput: parameter name too long: " + name);
    std::string p;
    PutU8(&p, static_cast<std::uint8_t>(key.size()));
    p += key;
    PutF32(&p, value);
    PutMessage(&out, 'P', p);
  }
  // 'A' subscriptions: msg_id = index of the series.
  for (std::size_t k = 0; k < in.series.size(); ++k) {
    std::string p;
    PutU8(&p, static_cast<std::uint8_t>(in.series[k].multi_id));
    PutU16(&p, static_cast<std::uint16_t>(k));
    p += in.series[k].topic;
    PutMessage(&out, 'A', p);
  }
  // State topics: msg_id = number of series + index.
  const std::size_t first_state = in.series.size();
  for (std::size_t k = 0; k < in.states.size(); ++k) {
    std::string p;
    PutU8(&p, 0);
    PutU16(&p, static_cast<std::uint16_t>(first_state + k));
    p += in.states[k].topic;
    PutMessage(&out, 'A', p);
  }
  // 'D' rows of every series merged by timestamp (ties: series order, then the state topics).
  auto times = [&](std::size_t k) -> const std::vector<std::uint64_t>& {
    return k < first_state ? in.series[k].timestamp_us : in.states[k - first_state].timestamp_us;
  };
  using Next = std::tuple<std::uint64_t, std::size_t, std::size_t>;  // time, series, row
  std::priority_queue<Next, std::vector<Next>, std::greater<Next>> heap;
  for (std::size_t k = 0; k < first_state + in.states.size(); ++k)
    if (!times(k).empty()) heap.emplace(times(k)[0], k, 0);
  while (!heap.empty()) {
    const auto [t, k, i] = heap.top();
    heap.pop();
    const auto id = static_cast<std::uint16_t>(k);
    PutMessage(&out, 'D', k < first_state ? DataRow(in.series[k], id, i) : StateRow(in.states[k - first_state], id, i));
    if (i + 1 < times(k).size()) heap.emplace(times(k)[i + 1], k, i + 1);
  }
  return out;
}

Result<std::string> EncodeULogGyro(const ULogGyroWriteInput& in) {
  const std::size_t n = in.timestamp_us.size();
  if (in.x_rad_s.size() != n || in.y_rad_s.size() != n || in.z_rad_s.size() != n || in.temperature_c.size() != n) {
    return InvalidArgument("ULogGyroWriteInput: x, y, z and temperature must have one value per timestamp (" +
                           std::to_string(n) + ")");
  }
  for (std::size_t i = 1; i < n; ++i) {
    if (in.timestamp_us[i] <= in.timestamp_us[i - 1]) {
      return InvalidArgument("ULogGyroWriteInput: timestamp_us not increasing at row " + std::to_string(i));
    }
  }
  if (in.sys_name.size() > 200) return InvalidArgument("ULogGyroWriteInput: sys_name longer than 200 characters");
  std::string out;
  // spec "File Header": magic, version 1, start timestamp.
  out.append("\x55\x4C\x6F\x67\x01\x12\x35", 7);
  PutU8(&out, 1);
  PutU64(&out, n > 0 ? in.timestamp_us.front() : 0);
  // 'B' flag bits: no compat, no incompat flags, no appended data.
  PutMessage(&out, 'B', std::string(40, '\0'));
  // 'I' info: uint8 key_len, "char[len] sys_name", value.
  {
    const std::string key = "char[" + std::to_string(in.sys_name.size()) + "] sys_name";
    std::string p;
    PutU8(&p, static_cast<std::uint8_t>(key.size()));
    p += key + in.sys_name;
    PutMessage(&out, 'I', p);
  }
  PutMessage(&out, 'F', kSensorGyroFormat);
  for (const auto& [name, value] : in.int_parameters) {
    const std::string key = "int32_t " + name;
    if (key.size() > 255) return InvalidArgument("ULogGyroWriteInput: parameter name too long: " + name);
    std::string p;
    PutU8(&p, static_cast<std::uint8_t>(key.size()));
    p += key;
    PutU32(&p, static_cast<std::uint32_t>(value));
    PutMessage(&out, 'P', p);
  }
  // 'A' subscription: multi_id 0, msg_id 0, "sensor_gyro".
  {
    std::string p;
    PutU8(&p, 0);
    PutU16(&p, 0);
    p += "sensor_gyro";
    PutMessage(&out, 'A', p);
  }
  std::string row;
  for (std::size_t i = 0; i < n; ++i) {
    row.clear();
    PutU16(&row, 0);                  // msg_id
    PutU64(&row, in.timestamp_us[i]);  // timestamp
    PutU64(&row, in.timestamp_us[i]);  // timestamp_sample
    PutU32(&row, in.device_id);
    PutF32(&row, in.x_rad_s[i]);
    PutF32(&row, in.y_rad_s[i]);
    PutF32(&row, in.z_rad_s[i]);
    PutF32(&row, in.temperature_c[i]);
    PutU32(&row, 0);  // error_count
    PutMessage(&out, 'D', row);
  }
  return out;
}

}  // namespace gyrocomp
