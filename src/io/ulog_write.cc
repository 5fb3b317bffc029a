// ULog writer of one sensor_gyro series (include/gyrocomp/io/ulog.h), following the message
// layouts of the PX4 "ULog File Format" spec; read back by ReadULog in the tests.
#include <cmath>
#include <cstring>
#include <string>

#include "gyrocomp/io/ulog.h"

namespace gyrocomp {

namespace {

// PX4's sensor_gyro message (msg/SensorGyro.msg), as its logger writes the format.
constexpr const char* kSensorGyroFormat =
    "sensor_gyro:uint64_t timestamp;uint64_t timestamp_sample;uint32_t device_id;float x;float y;float z;"
    "float temperature;uint32_t error_count;";

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

}  // namespace

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
