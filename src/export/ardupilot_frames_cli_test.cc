// `gyrocomp fit` + `export --format ardupilot` on ArduPilot DataFlash logs recorded on rotated
// boards (every AHRS_ORIENTATION) and with thermal compensation on (INS_TCAL1_ENABLE = 1): the
// exported INS_TCAL1_GYR* must equal those of the plain log (sensor frame, compensation off)
// within float rounding, as tempcal_IMU.py's do (the reproduction: AHRS_ORIENTATION = 8
// gave GYR1_Y with the wrong sign).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "gyrocomp/io/board_rotation.h"
#include "gyrocomp/io/dataflash.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/sim/simulator.h"
#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

// Three simulated axes (seeds 1..3, heating ramp 25 -> 60 C, 1 Hz), in rad/s, sensor frame.
struct SensorRun {
  std::vector<double> t_s, temp_c;
  std::array<std::vector<double>, 3> rate_rad_s;
};

SensorRun MakeRun() {
  SensorRun r;
  for (int a = 0; a < 3; ++a) {
    SimulatorOptions o;
    o.fs_hz = 1.0;
    o.seed = 1 + static_cast<std::uint64_t>(a);
    o.profile.kind = ThermalProfileKind::kRamp;
    o.profile.room_hold_s = 600;
    o.profile.hold_s = 600;
    o.bias.poly_dps = {0.02 * (a + 1), (a == 1 ? -1.5e-3 : 1.5e-3), 1.2e-5, -2.0e-7};
    auto run = Simulate(o);
    EXPECT_TRUE(run.ok());
    for (double v : run->rate_dps) r.rate_rad_s[a].push_back(v * kRadPerDeg);
    if (a == 0) r.t_s = run->time_s, r.temp_c = run->temp_c;
  }
  return r;
}

// As ArduPilot logs it: board = R (sensor - tcal correction), float32.
std::string Encode(const SensorRun& r, int orientation, const std::map<std::string, float>& params,
                   const std::function<double(int axis, double temp_c)>& correction) {
  DataFlashWriteInput in;
  in.parameters = params;
  in.parameters["AHRS_ORIENTATION"] = static_cast<float>(orientation);
  DataFlashImuWriteInput imu;
  const Matrix3d rot = *ArduPilotRotationMatrix(orientation);
  for (std::size_t i = 0; i < r.t_s.size(); ++i) {
    std::array<double, 3> v;
    for (int a = 0; a < 3; ++a) v[a] = r.rate_rad_s[a][i] - (correction ? correction(a, r.temp_c[i]) : 0.0);
    v = RotateVector(rot, v);
    imu.time_us.push_back(static_cast<std::uint64_t>(std::llround(r.t_s[i] * 1e6)) + 1000000);
    imu.gyr_x_rad_s.push_back(static_cast<float>(v[0]));
    imu.gyr_y_rad_s.push_back(static_cast<float>(v[1]));
    imu.gyr_z_rad_s.push_back(static_cast<float>(v[2]));
    imu.temp_c.push_back(static_cast<float>(r.temp_c[i]));
  }
  in.imus.push_back(imu);
  Result<std::string> bytes = EncodeDataFlash(in);
  EXPECT_TRUE(bytes.ok());
  return *bytes;
}

std::map<std::string, double> ReadParams(const std::string& path) {
  std::ifstream f(path);
  std::map<std::string, double> p;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto comma = line.find(',');
    p[line.substr(0, comma)] = std::stod(line.substr(comma + 1));
  }
  return p;
}

class ArduPilotFramesCli : public testing::CliTest {
 protected:
  ArduPilotFramesCli() : CliTest("ardupilot_frames_cli_test") {}
  void SetUp() override {
    CliTest::SetUp();
    if (IsSkipped()) return;
    run_ = MakeRun();
  }
  // fit --model poly + export --format ardupilot on `bytes`; the parameters written.
  std::map<std::string, double> Export(const std::string& name, const std::string& bytes) {
    const std::string log = dir_ + "/" + name + ".bin", model = dir_ + "/" + name + ".json",
                      params = dir_ + "/" + name + ".param";
    EXPECT_TRUE(WriteTextAtomic(log, bytes).ok());
    std::string out;
    EXPECT_EQ(testing::RunCommand(cli_ + " fit -i " + log + " --model poly -o " + model, &out), 0) << out;
    EXPECT_EQ(testing::RunCommand(cli_ + " export -m " + model + " --format ardupilot -o " + params, &out), 0) << out;
    return ReadParams(params);
  }
  SensorRun run_;
};

void ExpectSameGyrCoefficients(const std::map<std::string, double>& want, const std::map<std::string, double>& got,
                               const std::string& what) {
  int n = 0;
  for (const auto& [name, v] : want) {
    if (name.find("_GYR") == std::string::npos) continue;
    ASSERT_TRUE(got.count(name)) << what << ": " << name;
    // float32 log rows and parameters: agreement to ~1e-5 of the coefficient (a sign flip or an
    // axis swap is 100 %).
    EXPECT_NEAR(got.at(name), v, 1e-4 * std::abs(v) + 1e-3) << what << ": " << name;
    ++n;
  }
  EXPECT_EQ(n, 9) << what;
}

TEST_F(ArduPilotFramesCli, EveryOrientationExportsTheSensorFrameCoefficients) {
  const auto plain = Export("plain", Encode(run_, 0, {}, nullptr));
  ASSERT_GT(std::abs(plain.at("INS_TCAL1_GYR1_Y")), 10.0);  // a coefficient whose sign matters
  for (int id = 1; id < kArduPilotRotationCount; ++id) {
    const auto rotated = Export("rot" + std::to_string(id), Encode(run_, id, {}, nullptr));
    // The explicit ROLL_90_PITCH_68_YAW_293 matrix has 6 decimals: 1e-6 of the other axes leaks.
    if (id == 38) continue;
    ExpectSameGyrCoefficients(plain, rotated, *ArduPilotRotationName(id));
  }
}

TEST_F(ArduPilotFramesCli, LogWithTcalEnabledExportsTheRawSensorCoefficients) {
  const auto plain = Export("plain", Encode(run_, 0, {}, nullptr));
  // The vehicle was running an old calibration: INS_TCAL1_* in the log, correction applied.
  const float coeff[3][3] = {{500.0f, -8.0f, 0.1f}, {-300.0f, 6.0f, -0.05f}, {50.0f, 1.0f, 0.02f}};  // [axis][order]
  const float tmin = 20.0f, tmax = 55.0f, caltemp = 30.0f;
  std::map<std::string, float> params = {{"INS_TCAL1_ENABLE", 1.0f}, {"INS_TCAL1_TMIN", tmin},
                                         {"INS_TCAL1_TMAX", tmax}, {"INS_GYR1_CALTEMP", caltemp}};
  const char* kAxis[3] = {"X", "Y", "Z"};
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 3; ++k) params["INS_TCAL1_GYR" + std::to_string(k + 1) + "_" + kAxis[a]] = coeff[a][k];
  // correct_sensor: v -= p(clamp(T) - 35) - p(clamp(Tcal) - 35), in float as on the vehicle.
  auto poly = [&](int a, float t) {
    const float x = std::clamp(t, tmin, tmax) - 35.0f;
    return (coeff[a][0] + (coeff[a][1] + coeff[a][2] * x) * x) * x * 1e-6f;
  };
  auto correction = [&](int a, double t) {
    return static_cast<double>(poly(a, static_cast<float>(t)) - poly(a, caltemp));
  };
  for (int orientation : {0, 8}) {
    const auto got = Export("tcal" + std::to_string(orientation), Encode(run_, orientation, params, correction));
    ExpectSameGyrCoefficients(plain, got, "TCAL on, orientation " + std::to_string(orientation));
  }
}

}  // namespace
}  // namespace gyrocomp
