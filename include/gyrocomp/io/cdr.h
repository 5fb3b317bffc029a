// The two message encodings of ROS bags, for the two messages an IMU noise analysis needs:
// sensor_msgs/Imu and sensor_msgs/Temperature.
//
// ROS 2 (rmw / Fast-CDR, "cdr" message encoding of MCAP and rosbag2's sqlite3 storage):
//   OMG DDS-XTypes 1.3 section 7.4.3.5 "Data Representation": a 4-byte encapsulation header,
//   bytes 0-1 the representation identifier (0x0000 CDR_BE, 0x0001 CDR_LE: plain CDR / XCDR1),
//   bytes 2-3 options (ignored); then the body, in which every primitive is aligned to its own
//   size (1, 2, 4, 8), the alignment measured from the first byte after the header (OMG CORBA
//   3.3 part 2, section 9.3.1.1 "Alignment"; Fast-CDR resets its origin there). A string is a
//   uint32 length that counts the terminating NUL, then the bytes and the NUL (section 9.3.2.7).
//   The byte order is the header's.
// ROS 1 ("ros1" encoding of MCAP, ROS 1 bags): wiki.ros.org/roscpp/Overview/MessagesSerializationAndAdaptation
//   and wiki.ros.org/msg "Serialization": little-endian, packed (no alignment, no header); a
//   string is a uint32 length (no NUL counted) then the bytes; time is uint32 secs, uint32 nsecs;
//   std_msgs/Header starts with uint32 seq (removed in ROS 2).
//
// Message layouts (common_interfaces, sensor_msgs/msg/Imu.msg, Temperature.msg; std_msgs/msg/
// Header.msg; builtin_interfaces/msg/Time.msg: int32 sec, uint32 nanosec):
//   Imu: Header header; geometry_msgs/Quaternion orientation (float64 x, y, z, w);
//        float64[9] orientation_covariance; geometry_msgs/Vector3 angular_velocity (rad/s);
//        float64[9] angular_velocity_covariance; geometry_msgs/Vector3 linear_acceleration
//        (m/s^2); float64[9] linear_acceleration_covariance
//   Temperature: Header header; float64 temperature (deg C); float64 variance
// Decoders check every length against the message; trailing bytes are allowed (a message with
// more fields than this reader needs is still a message of that type, as Fast-CDR reads it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "gyrocomp/core/status.h"

namespace gyrocomp {

// The fields of sensor_msgs/Imu an IMU noise analysis uses.
struct ImuMessage {
  std::int64_t stamp_sec = 0;        // header.stamp.sec (ROS 2 int32, ROS 1 uint32 secs)
  std::uint32_t stamp_nanosec = 0;   // header.stamp.nanosec / nsecs
  double angular_velocity_rad_s[3] = {0, 0, 0};  // angular_velocity x, y, z, rad/s
  double linear_acceleration_m_s2[3] = {0, 0, 0};  // linear_acceleration x, y, z, m/s^2
  // header.stamp in integer nanoseconds (what the bag's receive times are in).
  std::int64_t StampNs() const { return stamp_sec * 1000000000 + static_cast<std::int64_t>(stamp_nanosec); }
};

// The fields of sensor_msgs/Temperature gyrocomp reads.
struct TemperatureMessage {
  std::int64_t stamp_sec = 0;  // header.stamp.sec (ROS 2 int32, ROS 1 uint32 secs)
  std::uint32_t stamp_nanosec = 0;  // header.stamp.nanosec / nsecs
  double temperature_c = 0.0;  // field temperature, deg C
  // header.stamp in integer nanoseconds.
  std::int64_t StampNs() const { return stamp_sec * 1000000000 + static_cast<std::int64_t>(stamp_nanosec); }
};

// A decoding failure: `offset` is the byte offset inside the message (0 = its first byte, the
// encapsulation header for CDR), `what` says what is wrong.
struct DecodeError {
  std::size_t offset = 0;  // byte offset in the message
  std::string what;  // what is wrong
};

// ROS 2 CDR (XCDR1, either byte order). Errors: an encapsulation other than CDR_BE / CDR_LE,
// a message shorter than the fields, a string length past the end or without its NUL, a
// nanosec >= 1e9.
std::optional<DecodeError> DecodeCdrImu(const std::uint8_t* data, std::size_t size, ImuMessage* out);
// sensor_msgs/Temperature in ROS 2 CDR (the same errors as DecodeCdrImu).
std::optional<DecodeError> DecodeCdrTemperature(const std::uint8_t* data, std::size_t size, TemperatureMessage* out);

// ROS 1 serialization.
std::optional<DecodeError> DecodeRos1Imu(const std::uint8_t* data, std::size_t size, ImuMessage* out);
// sensor_msgs/Temperature in ROS 1 serialization.
std::optional<DecodeError> DecodeRos1Temperature(const std::uint8_t* data, std::size_t size, TemperatureMessage* out);

// The same messages encoded (for tests and the simulators that write bags): CDR_LE or CDR_BE
// with an empty covariance and identity orientation; ROS 1 with seq = 0.
std::string EncodeCdrImu(const ImuMessage& m, const std::string& frame_id, bool big_endian);
// sensor_msgs/Temperature as CDR_LE or CDR_BE.
std::string EncodeCdrTemperature(const TemperatureMessage& m, const std::string& frame_id, bool big_endian);
// sensor_msgs/Imu in ROS 1 serialization.
std::string EncodeRos1Imu(const ImuMessage& m, const std::string& frame_id);
// sensor_msgs/Temperature in ROS 1 serialization.
std::string EncodeRos1Temperature(const TemperatureMessage& m, const std::string& frame_id);

}  // namespace gyrocomp
