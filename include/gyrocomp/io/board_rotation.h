// ArduPilot's board orientation (AHRS_ORIENTATION), the Rotation enum of
// libraries/AP_Math/rotations.h (ArduPilot/ardupilot, read at commit 17bcf931), as matrices.
//
// ArduPilot rotates every IMU sample from the sensor frame to the board frame with
// Vector3::rotate(AHRS_ORIENTATION) (libraries/AP_Math/vector3.cpp; applied in
// AP_InertialSensor_Backend::_rotate_and_correct_gyro / _accel after the offsets and the thermal
// correction), and the IMU rows of a DataFlash log are that board-frame vector. Its thermal
// parameters (INS_TCALn_*) are in the sensor frame, so ArduPilot's Tools/scripts/tempcal_IMU.py
// undoes the rotation (`gyr.rotate_by_inverse_id(orientation)`, read at commit d4209711) before
// fitting. gyrocomp does the same, in one place: FlightLogFromDataFlash (flight_log.cc).
//
// Every named rotation is R = Rz(yaw) Ry(pitch) Rx(roll) of the angles in its name (the
// convention of Matrix3::from_euler, which ArduPilot's rotations test suite checks rotate()
// against; pymavlink's rotmat.py builds its table the same way), except
// ROTATION_ROLL_90_PITCH_68_YAW_293, which vector3.cpp defines by an explicit matrix (copied).
// ROTATION_CUSTOM (100, 101, 102: CUST_ROT parameters) is not supported: refused with the reason.
#pragma once

#include <array>
#include <optional>
#include <string>

namespace gyrocomp {

// 3 x 3 rotation matrix, r[row][column].
using Matrix3d = std::array<std::array<double, 3>, 3>;

// Number of named rotations (ROTATION_NONE = 0 .. ROTATION_ROLL_315 = 43; ROTATION_MAX = 44).
inline constexpr int kArduPilotRotationCount = 44;

// The firmware's name of rotation `id` ("ROTATION_ROLL_180"), or nullopt for an id it does not
// define as a fixed rotation (>= 44, custom rotations 100..102).
std::optional<std::string> ArduPilotRotationName(int id);

// The matrix R with board = R * sensor, or nullopt as above.
std::optional<Matrix3d> ArduPilotRotationMatrix(int id);

// board = R v (Vector3::rotate) and sensor = R^T v (tempcal_IMU's rotate_by_inverse_id).
std::array<double, 3> RotateVector(const Matrix3d& r, const std::array<double, 3>& v);
// sensor = R^T v.
std::array<double, 3> RotateVectorInverse(const Matrix3d& r, const std::array<double, 3>& v);

}  // namespace gyrocomp
