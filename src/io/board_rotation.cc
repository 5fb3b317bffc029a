// ArduPilot board rotations (include/gyrocomp/io/board_rotation.h).
#include "gyrocomp/io/board_rotation.h"

#include <cmath>
#include <numbers>

namespace gyrocomp {
namespace {

struct NamedRotation {
  const char* name;
  double roll_deg, pitch_deg, yaw_deg;
};

// libraries/AP_Math/rotations.h, enum Rotation (ids are the index; read at commit 17bcf931).
// Angles as the names give them (pymavlink rotmat.py `rotations` has the same table up to id 41).
constexpr NamedRotation kRotations[kArduPilotRotationCount] = {
    {"ROTATION_NONE", 0, 0, 0},
    {"ROTATION_YAW_45", 0, 0, 45},
    {"ROTATION_YAW_90", 0, 0, 90},
    {"ROTATION_YAW_135", 0, 0, 135},
    {"ROTATION_YAW_180", 0, 0, 180},
    {"ROTATION_YAW_225", 0, 0, 225},
    {"ROTATION_YAW_270", 0, 0, 270},
    {"ROTATION_YAW_315", 0, 0, 315},
    {"ROTATION_ROLL_180", 180, 0, 0},
    {"ROTATION_ROLL_180_YAW_45", 180, 0, 45},
    {"ROTATION_ROLL_180_YAW_90", 180, 0, 90},
    {"ROTATION_ROLL_180_YAW_135", 180, 0, 135},
    {"ROTATION_PITCH_180", 0, 180, 0},
    {"ROTATION_ROLL_180_YAW_225", 180, 0, 225},
    {"ROTATION_ROLL_180_YAW_270", 180, 0, 270},
    {"ROTATION_ROLL_180_YAW_315", 180, 0, 315},
    {"ROTATION_ROLL_90", 90, 0, 0},
    {"ROTATION_ROLL_90_YAW_45", 90, 0, 45},
    {"ROTATION_ROLL_90_YAW_90", 90, 0, 90},
    {"ROTATION_ROLL_90_YAW_135", 90, 0, 135},
    {"ROTATION_ROLL_270", 270, 0, 0},
    {"ROTATION_ROLL_270_YAW_45", 270, 0, 45},
    {"ROTATION_ROLL_270_YAW_90", 270, 0, 90},
    {"ROTATION_ROLL_270_YAW_135", 270, 0, 135},
    {"ROTATION_PITCH_90", 0, 90, 0},
    {"ROTATION_PITCH_270", 0, 270, 0},
    {"ROTATION_PITCH_180_YAW_90", 0, 180, 90},
    {"ROTATION_PITCH_180_YAW_270", 0, 180, 270},
    {"ROTATION_ROLL_90_PITCH_90", 90, 90, 0},
    {"ROTATION_ROLL_180_PITCH_90", 180, 90, 0},
    {"ROTATION_ROLL_270_PITCH_90", 270, 90, 0},
    {"ROTATION_ROLL_90_PITCH_180", 90, 180, 0},
    {"ROTATION_ROLL_270_PITCH_180", 270, 180, 0},
    {"ROTATION_ROLL_90_PITCH_270", 90, 270, 0},
    {"ROTATION_ROLL_180_PITCH_270", 180, 270, 0},
    {"ROTATION_ROLL_270_PITCH_270", 270, 270, 0},
    {"ROTATION_ROLL_90_PITCH_180_YAW_90", 90, 180, 90},
    {"ROTATION_ROLL_90_YAW_270", 90, 0, 270},
    {"ROTATION_ROLL_90_PITCH_68_YAW_293", 0, 0, 0},  // explicit matrix below
    {"ROTATION_PITCH_315", 0, 315, 0},
    {"ROTATION_ROLL_90_PITCH_315", 90, 315, 0},
    {"ROTATION_PITCH_7", 0, 7, 0},
    {"ROTATION_ROLL_45", 45, 0, 0},
    {"ROTATION_ROLL_315", 315, 0, 0},
};
constexpr int kRoll90Pitch68Yaw293 = 38;

// Exact sin / cos of multiples of 45 deg (so ROLL_180 is exactly diag(1, -1, -1)).
void SinCosDeg(double deg, double* s, double* c) {
  const double rad = deg * std::numbers::pi / 180.0;
  *s = std::sin(rad);
  *c = std::cos(rad);
  if (std::fmod(deg, 90.0) == 0.0) {
    *s = std::round(*s);
    *c = std::round(*c);
  }
}

// Matrix3::from_euler(roll, pitch, yaw): R = Rz(yaw) Ry(pitch) Rx(roll).
Matrix3d FromEuler(double roll_deg, double pitch_deg, double yaw_deg) {
  double sr, cr, sp, cp, sy, cy;
  SinCosDeg(roll_deg, &sr, &cr);
  SinCosDeg(pitch_deg, &sp, &cp);
  SinCosDeg(yaw_deg, &sy, &cy);
  return {{{cp * cy, sr * sp * cy - cr * sy, cr * sp * cy + sr * sy},
           {cp * sy, sr * sp * sy + cr * cy, cr * sp * sy - sr * cy},
           {-sp, sr * cp, cr * cp}}};
}

}  // namespace

std::optional<std::string> ArduPilotRotationName(int id) {
  if (id < 0 || id >= kArduPilotRotationCount) return std::nullopt;
  return std::string(kRotations[id].name);
}

std::optional<Matrix3d> ArduPilotRotationMatrix(int id) {
  if (id < 0 || id >= kArduPilotRotationCount) return std::nullopt;
  if (id == kRoll90Pitch68Yaw293) {
    // libraries/AP_Math/vector3.cpp, Vector3::rotate, case ROTATION_ROLL_90_PITCH_68_YAW_293.
    return Matrix3d{{{0.143039, 0.368776, -0.918446},
                     {-0.332133, -0.856289, -0.395546},
                     {-0.932324, 0.361625, 0.000000}}};
  }
  const NamedRotation& r = kRotations[id];
  return FromEuler(r.roll_deg, r.pitch_deg, r.yaw_deg);
}

std::array<double, 3> RotateVector(const Matrix3d& r, const std::array<double, 3>& v) {
  std::array<double, 3> out{};
  for (int i = 0; i < 3; ++i) out[i] = r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2];
  return out;
}

std::array<double, 3> RotateVectorInverse(const Matrix3d& r, const std::array<double, 3>& v) {
  std::array<double, 3> out{};
  for (int i = 0; i < 3; ++i) out[i] = r[0][i] * v[0] + r[1][i] * v[1] + r[2][i] * v[2];
  return out;
}

}  // namespace gyrocomp
