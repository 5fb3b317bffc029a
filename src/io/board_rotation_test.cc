// ArduPilot board rotations against the firmware's own Vector3::rotate() cases
// (libraries/AP_Math/vector3.cpp, written out here for a few of them) and as rotations.
#include "gyrocomp/io/board_rotation.h"

#include <cmath>

#include <gtest/gtest.h>

namespace gyrocomp {
namespace {

constexpr double kHalfSqrt2 = 0.70710678118654757;

// A few cases of Vector3::rotate as the firmware writes them.
std::array<double, 3> FirmwareRotate(int id, std::array<double, 3> v) {
  double& x = v[0];
  double& y = v[1];
  double& z = v[2];
  double tmp = 0;
  switch (id) {
    case 1: tmp = kHalfSqrt2 * (x - y); y = kHalfSqrt2 * (x + y); x = tmp; break;          // YAW_45
    case 8: y = -y; z = -z; break;                                                          // ROLL_180
    case 10: tmp = x; x = y; y = tmp; z = -z; break;                                        // ROLL_180_YAW_90
    case 11: tmp = kHalfSqrt2 * (y - x); y = kHalfSqrt2 * (y + x); x = tmp; z = -z; break;  // ROLL_180_YAW_135
    case 18: tmp = z; z = y; y = -tmp; tmp = x; x = -y; y = tmp; break;                     // ROLL_90_YAW_90
    case 26: z = -z; tmp = -x; x = -y; y = tmp; break;                                      // PITCH_180_YAW_90
    case 27: x = -x; z = -z; tmp = x; x = y; y = -tmp; break;                               // PITCH_180_YAW_270
    case 36: tmp = z; z = y; y = -tmp; x = -x; z = -z; tmp = x; x = -y; y = tmp; break;     // ROLL_90_PITCH_180_YAW_90
    case 37: tmp = z; z = y; y = -tmp; tmp = x; x = y; y = -tmp; break;                     // ROLL_90_YAW_270
    case 40: tmp = z; z = y; y = -tmp; tmp = kHalfSqrt2 * (x - z); z = kHalfSqrt2 * (x + z); x = tmp; break;
    case 41: {  // PITCH_7
      const double s = 0.1218693434051474899781908334262, c = 0.99254615164132198312785249072476;
      const double tx = x, tz = z;
      x = c * tx + s * tz;
      z = -s * tx + c * tz;
      break;
    }
    case 43: tmp = kHalfSqrt2 * (y + z); z = kHalfSqrt2 * (z - y); y = tmp; break;  // ROLL_315
    default: ADD_FAILURE() << "no firmware case " << id;
  }
  return v;
}

TEST(BoardRotation, MatchesTheFirmwareRotateCases) {
  const std::array<double, 3> v = {0.3, -1.7, 2.9};
  for (int id : {1, 8, 10, 11, 18, 26, 27, 36, 37, 40, 41, 43}) {
    const auto r = ArduPilotRotationMatrix(id);
    ASSERT_TRUE(r) << id;
    const auto got = RotateVector(*r, v);
    const auto want = FirmwareRotate(id, v);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], 1e-14) << *ArduPilotRotationName(id) << " axis " << i;
  }
}

TEST(BoardRotation, EveryRotationIsOrthonormalAndInverts) {
  const std::array<double, 3> v = {0.3, -1.7, 2.9};
  for (int id = 0; id < kArduPilotRotationCount; ++id) {
    const auto r = ArduPilotRotationMatrix(id);
    ASSERT_TRUE(r) << id;
    // The explicit ROLL_90_PITCH_68_YAW_293 matrix has 6 decimals.
    const double tol = id == 38 ? 2e-6 : 1e-15;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double dot = 0;
        for (int k = 0; k < 3; ++k) dot += (*r)[i][k] * (*r)[j][k];
        EXPECT_NEAR(dot, i == j ? 1.0 : 0.0, tol) << id;
      }
    const auto back = RotateVectorInverse(*r, RotateVector(*r, v));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(back[i], v[i], 1e-5) << id;
  }
  EXPECT_EQ(*ArduPilotRotationName(8), "ROTATION_ROLL_180");
  EXPECT_EQ(*ArduPilotRotationName(43), "ROTATION_ROLL_315");
  EXPECT_FALSE(ArduPilotRotationMatrix(44));
  EXPECT_FALSE(ArduPilotRotationMatrix(100));  // ROTATION_CUSTOM
  EXPECT_FALSE(ArduPilotRotationMatrix(-1));
}

}  // namespace
}  // namespace gyrocomp
