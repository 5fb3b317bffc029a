// The calibrate stage called as a library (the CLI's own tests are src/export/calibrate*_cli_test.cc):
// a simulated 3-IMU board as a PX4 ULog and an ArduPilot DataFlash log -> every sensor calibrated,
// its cubic tracking the simulator's true drift, the parameter text and the table in the result;
// options out of range refused naming the field; logs of another kind refused; sensors matched
// across logs by device id when the boots enumerated the IMUs in another order; logs of another
// board refused.
#include "gyrocomp/calibrate/calibrate.h"

#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "gyrocomp/io/ulog.h"
#include "gyrocomp/sim/board_boot.h"
#include "gyrocomp/sim/simulator.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

double Variance(const std::vector<double>& v) {
  double m = 0.0, ss = 0.0;
  for (double x : v) m += x;
  m /= static_cast<double>(v.size());
  for (double x : v) ss += (x - m) * (x - m);
  return ss / static_cast<double>(v.size());
}

BoardRun Board(std::uint64_t seed) {
  BoardSimOptions o;
  o.chamber.profile.kind = ThermalProfileKind::kRamp;
  o.chamber.profile.ramp_end_c = 60.0;
  o.chamber.profile.room_hold_s = 600.0;
  o.chamber.profile.hold_s = 600.0;
  o.chamber.fs_hz = 10.0;
  o.chamber.seed = seed;
  o.num_imus = 3;
  Result<BoardRun> b = SimulateBoard(o);
  EXPECT_TRUE(b.ok()) << b.error().message;
  return *b;
}

TEST(Calibrate, EverySensorOfAPx4LogTheFileAndTheTable) {
  testing::TempDir dir("calibrate_test");
  const BoardRun board = Board(7);
  Result<std::string> bytes = EncodeBoardULog(board, board.fs_hz);
  ASSERT_TRUE(bytes.ok());
  const std::string log = testing::WriteFile(dir / "board.ulg", *bytes);
  Result<CalibrateResult> r = CalibrateLogs({log}, CalibrateOptions{});
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->sensors.size(), 7u);  // 3 gyros, 3 accels, 1 baro
  EXPECT_TRUE(r->AnyCalibrated());
  double ss_left = 0.0, ss_raw = 0.0;
  for (const CalibratedSensor& s : r->sensors) {
    ASSERT_TRUE(s.calibrated()) << s.type << s.instance << ": " << s.reason;
    EXPECT_EQ(s.cubics.size(), s.values.size());
    if (s.type != "gyro") continue;
    EXPECT_EQ(*s.device_id, BoardGyroDeviceId(s.instance));
    // The exported gyro cubic (PX4: the drift itself) against the simulator's true drift of its
    // IMU over the run, means removed: what the firmware leaves is well under the drift itself
    // (summed over the axes; the steady-state cubic does not follow the ramp's dT/dt share, and
    // the run's flicker noise is of the drift's size on single axes, so no per-axis bound).
    const BoardImuRun& truth = board.imus[static_cast<std::size_t>(s.instance)];
    for (std::size_t k = 0; k < 3; ++k) {
      std::vector<double> e_left, e_raw;
      for (std::size_t i = 0; i < truth.temp_c.size(); i += 10) {
        e_raw.push_back(truth.true_gyro_drift_rad_s[k][i]);
        e_left.push_back(truth.true_gyro_drift_rad_s[k][i] - s.cubics[k].Evaluate(truth.temp_c[i]));
      }
      ss_left += Variance(e_left), ss_raw += Variance(e_raw);
    }
  }
  std::printf("gyro drift RMS left / uncompensated: %.3g / %.3g rad/s\n", std::sqrt(ss_left / 9), std::sqrt(ss_raw / 9));
  EXPECT_LT(ss_left, 0.3 * ss_raw);  // RMS 0.55x at most (0.48x here)
  EXPECT_NE(r->parameter_text.find("TC_G_ENABLE"), std::string::npos);
  EXPECT_NE(r->parameter_text.find("TC_B0_ID"), std::string::npos);
  EXPECT_NE(r->BriefReport().find("gyro    2"), std::string::npos) << r->BriefReport();
  EXPECT_NE(ExpectedErrorText(r->sensors[0], false).find("steady"), std::string::npos);
}

TEST(Calibrate, ArduPilotLogGivesInsTcalAndNoBarometer) {
  testing::TempDir dir("calibrate_test");
  const BoardRun board = Board(8);
  Result<std::string> bytes = EncodeBoardDataFlash(board, board.fs_hz, 0);
  ASSERT_TRUE(bytes.ok());
  const std::string log = testing::WriteFile(dir / "board.bin", *bytes);
  CalibrateOptions o;
  o.format = "ardupilot";
  Result<CalibrateResult> r = CalibrateLogs({log}, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->sensors.size(), 6u);
  for (const CalibratedSensor& s : r->sensors) EXPECT_TRUE(s.calibrated()) << s.reason;
  EXPECT_NE(r->parameter_text.find("INS_TCAL3_GYR3_Z"), std::string::npos);
  // The wrong format for the log is an error naming both.
  o.format = "px4";
  Result<CalibrateResult> wrong = CalibrateLogs({log}, o);
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.error().message.find("PX4 parameters come from a ULog"), std::string::npos);
}

TEST(Calibrate, NothingCalibratableIsAResultWithReasonsAndNoText) {
  testing::TempDir dir("calibrate_test");
  const BoardRun board = Board(9);
  const std::string log = testing::WriteFile(dir / "board.ulg", *EncodeBoardULog(board, board.fs_hz));
  CalibrateOptions o;
  o.min_span_c = 100.0;
  Result<CalibrateResult> r = CalibrateLogs({log}, o);
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(r->AnyCalibrated());
  EXPECT_TRUE(r->parameter_text.empty());
  for (const CalibratedSensor& s : r->sensors) EXPECT_NE(s.reason.find("temperature span"), std::string::npos) << s.reason;
}

TEST(Calibrate, SensorsAreMatchedAcrossBootsByDeviceIdNotInstance) {
  testing::TempDir dir("calibrate_test");
  const BoardRun first = Board(11), second = Board(12);
  const std::string a = testing::WriteFile(dir / "a.ulg", *EncodeBoardULog(first, first.fs_hz));
  // The second boot enumerated the IMUs as 2, 0, 1: instance 0 is now the third chip.
  Result<std::string> bytes = EncodeBoardULogEnumerated(second, second.fs_hz, {2, 0, 1});
  ASSERT_TRUE(bytes.ok()) << bytes.error().message;
  const std::string b = testing::WriteFile(dir / "b.ulg", *bytes);
  Result<CalibrateResult> r = CalibrateLogs({a, b}, CalibrateOptions{});
  ASSERT_TRUE(r.ok()) << r.error().message;
  for (const CalibratedSensor& s : r->sensors) {
    ASSERT_TRUE(s.calibrated()) << s.type << " " << s.instance << ": " << s.reason;
    EXPECT_EQ(s.runs_combined, 2);
  }
  // The average is of the same chip's cubics: over the gyro axes, the combined cubics are nearer
  // their own chip's single-run cubics than the chips matched by instance would be (their drifts
  // scaled differently: BoardAxisDriftScale), over the common range, constants removed. Summed
  // over the 9 axes: on one axis the run's flicker noise is of the size of the difference.
  Result<CalibrateResult> alone = CalibrateLogs({a}, CalibrateOptions{});
  ASSERT_TRUE(alone.ok());
  auto distance2 = [](const TemperatureCubic& x, const TemperatureCubic& y) {
    std::vector<double> d;
    for (double t = x.temp_min_c; t <= x.temp_max_c; t += 0.5) d.push_back(x.Evaluate(t) - y.Evaluate(t));
    return Variance(d);
  };
  double own = 0.0, other = 0.0;
  for (int imu = 0; imu < 3; ++imu) {
    const CalibratedSensor& both = r->sensors[static_cast<std::size_t>(imu)];
    ASSERT_EQ(both.type, "gyro");
    const int by_instance = std::vector<int>{2, 0, 1}[static_cast<std::size_t>(imu)];
    for (std::size_t k = 0; k < 3; ++k) {
      own += distance2(both.cubics[k], alone->sensors[static_cast<std::size_t>(imu)].cubics[k]);
      other += distance2(both.cubics[k], alone->sensors[static_cast<std::size_t>(by_instance)].cubics[k]);
    }
  }
  std::printf("RMS to own chip / to the chip of the same instance: %.3g / %.3g rad/s\n", std::sqrt(own / 9), std::sqrt(other / 9));
  EXPECT_LT(own, 0.5 * other);
}

TEST(Calibrate, ALogOfAnotherBoardIsRefusedWithTheIds) {
  testing::TempDir dir("calibrate_test");
  const BoardRun board = Board(13);
  const std::string a = testing::WriteFile(dir / "a.ulg", *EncodeBoardULog(board, board.fs_hz));
  // Another board: one gyro and one accel whose device ids are on no sensor of the first.
  ULogWriteInput in;
  for (const char* topic : {"sensor_gyro", "sensor_accel"}) {
    ULogSensorWriteSeries s;
    s.topic = topic;
    s.device_id = 0x00ABCDEF;
    for (std::size_t i = 0; i < board.time_s.size(); ++i) {
      s.timestamp_us.push_back(static_cast<std::uint64_t>(board.time_s[i] * 1e6) + 1);
      s.x.push_back(0.0f), s.y.push_back(0.0f), s.z.push_back(0.0f);
      s.temperature_c.push_back(static_cast<float>(board.imus[0].temp_c[i]));
    }
    in.series.push_back(std::move(s));
  }
  const std::string other = testing::WriteFile(dir / "other.ulg", *EncodeULog(in));
  Result<CalibrateResult> r = CalibrateLogs({a, other}, CalibrateOptions{});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("another board"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find(std::to_string(0x00ABCDEF)), std::string::npos) << r.error().message;
  CalibrateOptions o;
  o.validation_path = other;
  Result<CalibrateResult> v = CalibrateLogs({a}, o);
  ASSERT_FALSE(v.ok());
  EXPECT_NE(v.error().message.find("another board"), std::string::npos) << v.error().message;
}

TEST(CalibrateOptions, OutOfRangeNamesTheField) {
  std::string why;
  EXPECT_TRUE(CalibrateOptions{}.IsValid(&why));
  CalibrateOptions o;
  o.fit_rate_hz = 0.0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("CalibrateOptions::fit_rate_hz"), std::string::npos) << why;
  o = {};
  o.static_weight = "median";
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("static_weight"), std::string::npos) << why;
  o = {};
  o.format = "betaflight";
  EXPECT_FALSE(o.IsValid(&why));
  Result<CalibrateResult> r = CalibrateLogs({"/nonexistent.ulg"}, o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("format"), std::string::npos);
}

}  // namespace
}  // namespace gyrocomp
