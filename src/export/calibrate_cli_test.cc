// `gyrocomp calibrate` end to end (docs/guides/calibrate-board.md): simulated 3-IMU boards as a PX4
// ULog and an ArduPilot DataFlash log -> one parameter file each; every coefficient evaluated with
// the firmware's own formula (written here in float, as on the vehicle) equals gyrocomp's cubic
// (the JSON's) within 2e-6 (rad/s, m/s^2); the file follows QGroundControl's format rules / loads
// with pymavlink's MAVParmDict.load (when GYROCOMP_PYMAVLINK_DIR names a pymavlink source tree); a
// rotated board gives the same parameters; nothing calibratable is an error with no file written.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "gyrocomp/export/thermal_cubic.h"
#include "gyrocomp/sim/simulator.h"
#include "param_files_test_util.h"
#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

// QGroundControl (param_files_test_util.h): names <= 16 characters (MAVLink param_id), TYPE 6
// (INT32) for IDs and enables, 9 (REAL32) otherwise.
std::map<std::string, std::string> ReadQgc(const std::string& text) {
  const testing::QgcFile file = testing::ReadQgcFile(text);
  EXPECT_TRUE(file.has_column_header);
  std::map<std::string, std::string> p;
  for (const auto& [name, param] : file.params) {
    EXPECT_LE(name.size(), 16u) << name;
    const bool integer = name.ends_with("_ID") || name.ends_with("_ENABLE");
    EXPECT_EQ(param.type, integer ? "6" : "9") << name;
    p[name] = param.value;
  }
  return p;
}

TemperatureCubic CubicOf(const nlohmann::json& axis) {
  TemperatureCubic c;
  c.ref_temp_c = axis["cubic"]["ref_temp_c"].get<double>();
  c.temp_min_c = axis["cubic"]["temp_min_c"].get<double>();
  c.temp_max_c = axis["cubic"]["temp_max_c"].get<double>();
  c.coeff = axis["cubic"]["coeff"].get<std::array<double, 4>>();
  return c;
}

// PX4 TemperatureCompensation::calc_thermal_offsets_3D / _1D, in float.
float Px4Offset(const std::map<std::string, std::string>& p, const std::string& s, const std::string& sfx, float temp) {
  auto f = [&](const std::string& n) { return std::stof(p.at(s + n)); };
  const float tmin = f("TMIN"), tmax = f("TMAX"), tref = f("TREF");
  const float dt = temp > tmax ? tmax - tref : temp < tmin ? tmin - tref : temp - tref;
  const float dt2 = dt * dt, dt3 = dt2 * dt;
  return f("X0" + sfx) + f("X1" + sfx) * dt + f("X2" + sfx) * dt2 + f("X3" + sfx) * dt3;
}

// ArduPilot correct_sensor: what it removes at T after the boot offset at Tcal, in float.
float ApRemoved(const std::map<std::string, float>& p, const std::string& pre, const char* kind, char axis, float t,
                float tcal) {
  const float tmin = p.at(pre + "TMIN"), tmax = p.at(pre + "TMAX");
  auto poly = [&](float x) {
    const std::string k = pre + kind;
    const float c1 = p.at(k + "1_" + axis), c2 = p.at(k + "2_" + axis), c3 = p.at(k + "3_" + axis);
    return (c1 + (c2 + c3 * x) * x) * x * 1.0e-6f;
  };
  return poly(std::clamp(t, tmin, tmax) - 35.0f) - poly(std::clamp(tcal, tmin, tmax) - 35.0f);
}

class CalibrateCli : public testing::CliTest {
 protected:
  CalibrateCli() : CliTest("calibrate_cli_test") {}
  std::string Simulate(const std::string& name, const std::string& extra) {
    std::string out;
    const std::string path = dir_ + "/" + name;
    EXPECT_EQ(Run("simulate --profile ramp --ramp-end 60 --room-hold 600 --hold 600 --fs 10 --imus 3 " + extra +
                      " -o " + path, &out), 0) << out;
    return path;
  }
};

TEST_F(CalibrateCli, Px4FileHoldsEverySensorAndTheFirmwareFormulaGivesTheCubic) {
  const std::string log = Simulate("board.ulg", "");
  std::string out;
  ASSERT_EQ(Run("calibrate -i " + log + " --format px4 -o " + dir_ + "/tc.params --models " + dir_ +
                    "/models --json " + dir_ + "/cal.json", &out), 0) << out;
  EXPECT_NE(out.find("gyro 2 (id "), std::string::npos) << out;  // the console summary, one line per sensor
  const auto p = ReadQgc(testing::ReadFile(dir_ + "/tc.params"));
  const nlohmann::json j = testing::ReadJsonFile(dir_ + "/cal.json");
  ASSERT_EQ(j["sensors"].size(), 7u);  // 3 gyros, 3 accels, 1 baro
  EXPECT_EQ(p.at("TC_G_ENABLE"), "1");
  EXPECT_EQ(p.at("TC_A_ENABLE"), "1");
  EXPECT_EQ(p.at("TC_B_ENABLE"), "1");
  EXPECT_EQ(p.at("TC_G3_ID"), "0");  // unused slot
  int checked = 0;
  for (const auto& s : j["sensors"]) {
    ASSERT_EQ(s["status"], "calibrated") << s.dump();
    const std::string type = s["type"];
    const int slot = s["slot"];
    const std::string pre = std::string("TC_") + (type == "gyro" ? "G" : type == "accel" ? "A" : "B") + std::to_string(slot) + "_";
    EXPECT_EQ(p.at(pre + "ID"), std::to_string(s["device_id"].get<std::uint32_t>()));
    if (type == "gyro") {
      EXPECT_EQ(s["device_id"].get<std::uint32_t>(), BoardGyroDeviceId(slot));
    } else if (type == "accel") {
      EXPECT_EQ(s["device_id"].get<std::uint32_t>(), BoardAccelDeviceId(slot));
    }
    EXPECT_TRUE(fs::exists(dir_ + "/models/" + type + std::to_string(s["instance"].get<int>()) + ".json"));
    for (std::size_t a = 0; a < s["axes"].size(); ++a) {
      const TemperatureCubic c = CubicOf(s["axes"][a]);
      for (double t = 15.0; t <= 70.0; t += 0.9) {
        float fw;
        if (type == "baro") {
          // calc_thermal_offsets_1D (quintic; X4 = X5 = 0 here).
          auto f = [&](const std::string& n) { return std::stof(p.at(pre + n)); };
          const float tf = static_cast<float>(t);
          const float dt = tf > f("TMAX") ? f("TMAX") - f("TREF") : tf < f("TMIN") ? f("TMIN") - f("TREF") : tf - f("TREF");
          fw = f("X0") + f("X1") * dt + f("X2") * dt * dt + f("X3") * dt * dt * dt + f("X4") * dt * dt * dt * dt;
          EXPECT_NEAR(fw, c.Evaluate(t), 2e-6 * 100) << pre << " T " << t;  // Pa (float ulp of 1e2 Pa terms)
        } else {
          fw = Px4Offset(p, pre, "_" + std::to_string(a), static_cast<float>(t));
          EXPECT_NEAR(fw, c.Evaluate(t), 2e-6) << pre << a << " T " << t;
        }
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST_F(CalibrateCli, ArduPilotFileIsRelativeToTheBootOffsetAndIgnoresBoardRotation) {
  std::map<std::string, float> params[2];
  nlohmann::json jsons[2];
  for (int r = 0; r < 2; ++r) {
    const std::string log = Simulate("board" + std::to_string(r) + ".bin", r == 0 ? "" : "--ahrs-orientation 8");
    std::string out;
    const std::string file = dir_ + "/tc" + std::to_string(r) + ".param", json = dir_ + "/cal" + std::to_string(r) + ".json";
    ASSERT_EQ(Run("calibrate -i " + log + " --format ardupilot -o " + file + " --json " + json, &out), 0) << out;
    params[r] = testing::ReadMissionPlannerFile(testing::ReadFile(file));
    jsons[r] = testing::ReadJsonFile(json);
  }
  const auto& p = params[0];
  EXPECT_EQ(p.size(), 3u * 21u);
  for (const auto& s : jsons[0]["sensors"]) {
    ASSERT_EQ(s["status"], "calibrated");
    const std::string pre = "INS_TCAL" + std::to_string(s["imu"].get<int>()) + "_";
    EXPECT_EQ(p.at(pre + "ENABLE"), 1.0f);
    const char* kind = s["type"] == "gyro" ? "GYR" : "ACC";
    for (int a = 0; a < 3; ++a) {
      const TemperatureCubic c = CubicOf(s["axes"][a]);
      for (double tcal : {20.0, 35.0, 47.0})
        for (double t = 15.0; t <= 70.0; t += 1.3) {
          const double want = c.Evaluate(t) - c.Evaluate(tcal);  // drift(T) - drift(Tcal): offsets absorb the rest
          EXPECT_NEAR(ApRemoved(p, pre, kind, "XYZ"[a], static_cast<float>(t), static_cast<float>(tcal)), want, 2e-6)
              << pre << kind << a << " T " << t;
        }
    }
  }
  // The same board logged with AHRS_ORIENTATION = 8 (roll 180): the same sensor-frame parameters.
  for (const auto& [name, v] : params[0]) {
    ASSERT_TRUE(params[1].count(name)) << name;
    EXPECT_NEAR(params[1].at(name), v, 1e-4 * std::abs(v) + 1e-3) << name;
  }
}

TEST_F(CalibrateCli, PymavlinkLoadsTheArduPilotFile) {
  const char* dir = std::getenv("GYROCOMP_PYMAVLINK_DIR");
  if (!dir) GTEST_SKIP() << "set GYROCOMP_PYMAVLINK_DIR to a pymavlink source tree (its mavparm.py) to run this";
  const std::string log = Simulate("board.bin", "");
  std::string out;
  ASSERT_EQ(Run("calibrate -i " + log + " --format ardupilot -o " + dir_ + "/tc.param", &out), 0) << out;
  // mavparm.py imports pymavlink.mavutil only for talking to a vehicle (mavset); load() needs
  // none of it, so a stub stands in for it.
  const std::string py =
      "import sys, types, importlib.util\n"
      "pkg = types.ModuleType('pymavlink'); pkg.__path__ = []; sys.modules['pymavlink'] = pkg\n"
      "mu = types.ModuleType('pymavlink.mavutil'); sys.modules['pymavlink.mavutil'] = mu; pkg.mavutil = mu\n"
      "spec = importlib.util.spec_from_file_location('pymavlink.mavparm', sys.argv[1] + '/mavparm.py')\n"
      "m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m)\n"
      "p = m.MAVParmDict()\n"
      "assert p.load(sys.argv[2]) is not False\n"
      "print(len(p), p['INS_TCAL1_ENABLE'], p['INS_TCAL3_GYR3_Z'])\n";
  std::ofstream(dir_ + "/load.py") << py;
  ASSERT_EQ(testing::RunCommand("/usr/bin/python3 " + dir_ + "/load.py " + dir + " " + dir_ + "/tc.param", &out), 0) << out;
  EXPECT_NE(out.find("63 1.0 "), std::string::npos) << out;  // every line loaded, none "Invalid line"
  EXPECT_EQ(out.find("Invalid line"), std::string::npos) << out;
}

TEST_F(CalibrateCli, NothingCalibratableIsAnErrorAndNoFile) {
  const std::string log = Simulate("board.ulg", "");
  std::string out;
  EXPECT_EQ(Run("calibrate -i " + log + " --format px4 --min-span 100 -o " + dir_ + "/tc.params", &out), 2) << out;
  EXPECT_NE(out.find("temperature span"), std::string::npos) << out;   // each row keeps its reason
  EXPECT_NE(out.find("no sensor could be calibrated"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir_ + "/tc.params"));
  // A ULog with --format ardupilot is refused with the reason.
  EXPECT_EQ(Run("calibrate -i " + log + " --format ardupilot -o " + dir_ + "/x.param", &out), 2) << out;
  EXPECT_NE(out.find("PX4 parameters come from a ULog"), std::string::npos) << out;
}

// A real PX4 log (tests/fieldlogs, 6 rows per sensor): every sensor_gyro / accel / baro instance
// is read and keeps its row with the reason; nothing calibratable -> exit 2.
TEST_F(CalibrateCli, RealPx4LogListsEverySensorWithItsReason) {
  const std::string ulg = testing::FieldlogsDir() + "/sample_log_small.ulg";
  if (!fs::exists(ulg)) GTEST_SKIP() << "tests/fieldlogs/sample_log_small.ulg absent";
  std::string out;
  EXPECT_EQ(Run("calibrate -i '" + ulg + "' --format px4 -o " + dir_ + "/x.params", &out), 2) << out;
  for (const char* sensor : {"gyro 2 (id ", "accel 2 (id ", "baro 1 (id "}) {
    const std::size_t at = out.find(sensor);
    ASSERT_NE(at, std::string::npos) << sensor << "\n" << out;
    const std::string line = out.substr(at, out.find('\n', at) - at);
    EXPECT_NE(line.find("skipped, 6 rows"), std::string::npos) << line;
  }
  EXPECT_FALSE(fs::exists(dir_ + "/x.params"));
}

}  // namespace
}  // namespace gyrocomp
