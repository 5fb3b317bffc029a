// `gyrocomp calibrate` on several logs of one board (docs/guides/calibrate-from-flights.md): what
// differs between the logs and is not refused is said once on the console, naming both files and
// both values, and the file is written (exit 0): a board rotation (AHRS_ORIENTATION; each log is
// rotated back with its own value) and a log rate (the fit sees 1 s means of each log). What is
// refused, a log of another board, is one line (exit 2) and no file.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include "fixtures.h"
#include "gyrocomp/io/ulog.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

class CalibrateLogsCli : public testing::CliTest {
 protected:
  CalibrateLogsCli() : CliTest("calibrate_logs_cli_test") {}
  std::string Simulate(const std::string& name, const std::string& extra) {
    std::string out;
    const std::string path = dir_ + "/" + name;
    EXPECT_EQ(Run("simulate --profile ramp --ramp-end 60 --room-hold 600 --hold 600 --fs 10 --imus 1 " + extra + " -o " + path, &out), 0)
        << out;
    return path;
  }
};

TEST_F(CalibrateLogsCli, ARotationChangeIsNotedAndTheFileWritten) {
  const std::string a = Simulate("a.bin", "--seed 3"), b = Simulate("b.bin", "--seed 4 --ahrs-orientation 8");
  std::string out;
  ASSERT_EQ(Run("calibrate -i " + a + " -i " + b + " --format ardupilot -o " + dir_ + "/tc.param", &out), 0) << out;
  EXPECT_NE(out.find("AHRS_ORIENTATION = 0 in " + a + ", 8 in " + b + ": pooled all the same"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir_ + "/tc.param"));
}

TEST_F(CalibrateLogsCli, ALogRateChangeIsNotedAndTheFileWritten) {
  const std::string a = Simulate("a.ulg", "--seed 3"), b = Simulate("b.ulg", "--seed 4 --log-rate 5");
  std::string out;
  ASSERT_EQ(Run("calibrate -i " + a + " -i " + b + " --format px4 -o " + dir_ + "/tc.params", &out), 0) << out;
  EXPECT_NE(out.find("logged at 10 Hz in " + a + ", 5 Hz in " + b + ": pooled all the same"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir_ + "/tc.params"));
}

// A pooled fit has no static weighting: --static-weight given with several logs is said on one
// line not to apply (not an error). --optimise-for applies (the kept dT/dt gain or lag at the logs'
// heating state): the header says the condition, per sensor what it did, and no note calls it
// ignored; where no sensor kept a term a note says the condition changes nothing.
TEST_F(CalibrateLogsCli, StaticWeightIsSaidNotToApplyToAPooledFitAndOptimiseForIsHonoured) {
  const std::string a = Simulate("a.ulg", "--seed 3"), b = Simulate("b.ulg", "--seed 4");
  std::string out;
  ASSERT_EQ(Run("calibrate -i " + a + " -i " + b + " --format px4 --static-weight time --optimise-for warm-up -o " + dir_ +
                    "/tc.params",
                &out),
            0)
      << out;
  const std::string note = "--static-weight ignored: it does not apply to a pooled fit";
  ASSERT_NE(out.find(note), std::string::npos) << out;
  EXPECT_EQ(out.find(note, out.find(note) + 1), std::string::npos) << out;  // once
  EXPECT_EQ(out.find("--optimise-for and --static-weight ignored"), std::string::npos) << out;
  EXPECT_EQ(out.find("--optimise-for ignored"), std::string::npos) << out;
  const std::string text = testing::ReadFile(dir_ + "/tc.params");
  EXPECT_EQ(text.find("static curve weighted by"), std::string::npos) << text;
  EXPECT_EQ(text.find("do not apply"), std::string::npos) << text;
  EXPECT_NE(text.find("Optimised for: warm-up"), std::string::npos) << text;
  EXPECT_NE(text.find("optimised for warm-up: "), std::string::npos) << text;  // per sensor, what it did
  EXPECT_NE(text.find("one least-squares cubic in temperature over the"), std::string::npos) << text;
  EXPECT_NE(text.find("fitted on the "), std::string::npos) << text;
  // Without the options: no note, and the header says steady.
  ASSERT_EQ(Run("calibrate -i " + a + " -i " + b + " --format px4 -o " + dir_ + "/tc2.params", &out), 0) << out;
  EXPECT_EQ(out.find("do not apply"), std::string::npos) << out;
  EXPECT_EQ(out.find("does not apply"), std::string::npos) << out;
  EXPECT_NE(testing::ReadFile(dir_ + "/tc2.params").find("Optimised for: steady"), std::string::npos);
  EXPECT_EQ(out.find("changes nothing here"), std::string::npos) << out;  // steady: no such note
  // A board with no dT/dt drift: the note that the condition changes nothing exactly when every
  // sensor's header line says it kept no term.
  const std::string c = Simulate("c.ulg", "--seed 5 --dtemp-coeff 0 --hysteresis-coeff 0"),
                    d = Simulate("d.ulg", "--seed 6 --dtemp-coeff 0 --hysteresis-coeff 0");
  ASSERT_EQ(Run("calibrate -i " + c + " -i " + d + " --format px4 --optimise-for both -o " + dir_ + "/tc3.params", &out), 0) << out;
  const std::string text3 = testing::ReadFile(dir_ + "/tc3.params");
  const bool any_term = text3.find("the curve + dT/dt gain") != std::string::npos || text3.find("the lagged curve") != std::string::npos;
  EXPECT_NE(text3.find("optimised for both: "), std::string::npos) << text3;
  EXPECT_EQ(out.find("--optimise-for both changes nothing here") != std::string::npos, !any_term) << out << text3;
}

// --verbose on a pooled fit: each sensor's rows say what the pooled fit has (lag, dT/dt gain,
// curve 1 sigma, what the cubic leaves steady and at the heating state), not a single run's
// projection cost, expected next-run error or static weighting, which it does not have.
TEST_F(CalibrateLogsCli, VerbosePooledTableShowsThePooledFitNotTheSingleRunColumns) {
  const std::string a = Simulate("a.ulg", "--seed 3"), b = Simulate("b.ulg", "--seed 4");
  std::string out;
  ASSERT_EQ(Run("calibrate -i " + a + " -i " + b + " --format px4 --optimise-for both -v -o " + dir_ + "/tc.params", &out), 0) << out;
  for (const char* want : {"pooled over 2 log(s), lag ", " s, dT/dt gain ", "curve 1 sigma (pooled fit)",
                           "optimised for both: cubic - curve steady", ", at the heating state"})
    EXPECT_NE(out.find(want), std::string::npos) << want << "\n" << out;
  for (const char* not_there : {"expected next-run error of the cubic", "static weight"})
    EXPECT_EQ(out.find(not_there), std::string::npos) << not_there << "\n" << out;
  // A single run keeps its columns.
  ASSERT_EQ(Run("calibrate -i " + a + " --format px4 -v -o " + dir_ + "/one.params", &out), 0) << out;
  EXPECT_NE(out.find("expected next-run error of the cubic"), std::string::npos) << out;
  EXPECT_EQ(out.find("dT/dt gain"), std::string::npos) << out;
}

// A pooled sensor that kept a dT/dt term (or a lag), which the firmware's cubic cannot carry: the
// console says on one line what the exported cubic leaves in the condition it was not made for,
// naming only sensors that kept such a term (the JSON's heating_state) and where it matters. Two
// heating runs, 10 -> 60 C at 1 and 3 C/min, of the simulator's default drift (1.5 deg/s per C/s)
// identify the gyro's gain: its trade is most of its drift, so it is named, first; the baro, which
// keeps no term, is not.
TEST_F(CalibrateLogsCli, AKeptRateTermIsSaidWithWhatTheCubicLeaves) {
  const std::string a = Simulate("a.ulg", "--seed 3 --room-temp 10 --thermal-lag 120"),
                    b = Simulate("b.ulg", "--seed 4 --room-temp 10 --thermal-lag 120 --ramp-rate 3");
  for (const std::string condition : {"steady", "warm-up"}) {
    std::string out;
    const std::string json = dir_ + "/tc_" + condition + ".json";
    ASSERT_EQ(Run("calibrate -i " + a + " -i " + b + " --format px4 --optimise-for " + condition + " --json " + json + " -o " +
                      dir_ + "/tc.params",
                  &out),
              0)
        << out;
    const std::string tail = condition == "steady"
                                 ? " a firmware cubic cannot carry: the steady cubic leaves "
                                 : ": the cubic optimised for warm-up leaves ";
    const std::size_t at = out.find(tail);
    ASSERT_NE(at, std::string::npos) << out;
    const std::size_t start = out.rfind("\n  ", at) + 3;
    const std::string names = out.substr(start, out.rfind(" kept a", at) - start);
    ASSERT_EQ(names.rfind("gyro 0", 0), 0u) << out;  // the case this test is about, first
    const nlohmann::json doc = testing::ReadJsonFile(json);
    int without = 0;
    for (const nlohmann::json& s : doc["sensors"]) {
      const std::string name = s["type"].get<std::string>() + " " + std::to_string(s["instance"].get<int>());
      const bool term = s.contains("heating_state") && !s["heating_state"].is_null();
      if (!term) {
        ++without;
        EXPECT_EQ(names.find(name), std::string::npos) << name << " named without a term\n" << out;
      }
      if (name == "gyro 0") {
        EXPECT_EQ(s["heating_state"]["kind"], "dtemp_c_per_s") << out;
      }
    }
    EXPECT_GE(without, 1) << out;  // the baro: a sensor the line must not name
    EXPECT_NE(out.find(condition == "steady" ? " mdps while heating at the logs' rate (--optimise-for warm-up trades that against cooling)"
                                             : " when the temperature is steady, more while cooling"),
              std::string::npos)
        << out;
  }
}

TEST_F(CalibrateLogsCli, ALogOfAnotherBoardIsRefusedOnOneLineAndNoFile) {
  const std::string a = Simulate("a.ulg", "--seed 3");
  // A gyro of device id 12345 (none of the simulated board's), ten minutes at 1 Hz.
  ULogWriteInput in;
  ULogSensorWriteSeries g;
  g.topic = "sensor_gyro", g.device_id = 12345;
  for (int i = 0; i < 600; ++i) {
    g.timestamp_us.push_back(1000000ull * static_cast<std::uint64_t>(i + 1));
    g.x.push_back(0.f), g.y.push_back(0.f), g.z.push_back(0.f), g.temperature_c.push_back(20.f + 0.02f * static_cast<float>(i));
  }
  in.series.push_back(g);
  const std::string b = Put("other.ulg", *EncodeULog(in));
  ExpectRefused("calibrate -i " + a + " -i " + b + " --format px4 -o " + dir_ + "/tc.params",
                {b + ": a log of another board", "12345"});
  EXPECT_FALSE(fs::exists(dir_ + "/tc.params"));
}

}  // namespace
}  // namespace gyrocomp
