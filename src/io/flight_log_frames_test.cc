// ArduPilot logs brought back to the sensor frame (flight_log.h, DataFlashImuToSensorFrame): the
// board rotation AHRS_ORIENTATION undone for every fixed rotation, the log's own INS_TCALn_*
// correction added back with correct_sensor's formula, bad orientations refused; PX4 sensor_gyro
// never flagged as compensated (TC_G_ENABLE acts after it).
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/io/board_rotation.h"
#include "gyrocomp/io/dataflash.h"
#include "gyrocomp/io/flight_log.h"

namespace gyrocomp {
namespace {

constexpr int kFrameRows = 200;

// Sensor-frame truth: a drift in T on each axis plus gravity on the accel's z.
double TempC(int i) { return 10.0 + 0.25 * i; }
std::array<double, 3> Gyro(int i) {
  const double x = TempC(i) - 35.0;
  return {1e-3 * x, -2e-3 * x + 1e-5 * x * x, 0.01 + 3e-7 * x * x * x};
}
std::array<double, 3> Accel(int i) {
  const double x = TempC(i) - 35.0;
  return {0.02 * x, -0.01 * x, -9.80665 + 1e-4 * x * x};
}

// A one-IMU log whose rows are what ArduPilot logs: R * (sensor - correction).
DataFlashContents Log(int orientation, const std::map<std::string, float>& params,
                      const std::function<std::array<double, 3>(int, int, std::array<double, 3>)>& correct = nullptr) {
  DataFlashWriteInput in;
  in.parameters = params;
  if (orientation != 0) in.parameters["AHRS_ORIENTATION"] = static_cast<float>(orientation);
  DataFlashImuWriteInput imu;
  const auto r = ArduPilotRotationMatrix(orientation);
  for (int i = 0; i < kFrameRows; ++i) {
    imu.time_us.push_back(1000000 + 10000 * static_cast<std::uint64_t>(i));
    auto g = Gyro(i), a = Accel(i);
    if (correct) g = correct(0, i, g), a = correct(1, i, a);
    if (r) g = RotateVector(*r, g), a = RotateVector(*r, a);
    imu.gyr_x_rad_s.push_back(static_cast<float>(g[0]));
    imu.gyr_y_rad_s.push_back(static_cast<float>(g[1]));
    imu.gyr_z_rad_s.push_back(static_cast<float>(g[2]));
    imu.acc_x_m_s2.push_back(static_cast<float>(a[0]));
    imu.acc_y_m_s2.push_back(static_cast<float>(a[1]));
    imu.acc_z_m_s2.push_back(static_cast<float>(a[2]));
    imu.temp_c.push_back(static_cast<float>(TempC(i)));
  }
  in.imus.push_back(imu);
  Result<std::string> bytes = EncodeDataFlash(in);
  EXPECT_TRUE(bytes.ok());
  Result<DataFlashContents> log =
      ParseDataFlash(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size(), "mem.bin");
  EXPECT_TRUE(log.ok()) << log.error().message;
  return *log;
}

void ExpectSensorFrame(const DataFlashImuSeries& s, double tol, const std::string& what) {
  ASSERT_EQ(s.time_us.size(), static_cast<std::size_t>(kFrameRows));
  ASSERT_EQ(s.acc_x_m_s2.size(), static_cast<std::size_t>(kFrameRows));
  for (int i = 0; i < kFrameRows; ++i) {
    const auto g = Gyro(i), a = Accel(i);
    ASSERT_NEAR(s.gyr_x_rad_s[i], g[0], tol) << what << " row " << i;
    ASSERT_NEAR(s.gyr_y_rad_s[i], g[1], tol) << what << " row " << i;
    ASSERT_NEAR(s.gyr_z_rad_s[i], g[2], tol) << what << " row " << i;
    ASSERT_NEAR(s.acc_x_m_s2[i], a[0], 20 * tol) << what << " row " << i;
    ASSERT_NEAR(s.acc_y_m_s2[i], a[1], 20 * tol) << what << " row " << i;
    ASSERT_NEAR(s.acc_z_m_s2[i], a[2], 20 * tol) << what << " row " << i;
  }
}

TEST(FlightLogFrames, EveryAhrsOrientationIsUndone) {
  for (int id = 0; id < kArduPilotRotationCount; ++id) {
    const DataFlashContents log = Log(id, {});
    std::vector<std::string> notes;
    Result<DataFlashImuSeries> s = DataFlashImuToSensorFrame(log, log.imus[0], &notes);
    ASSERT_TRUE(s.ok()) << s.error().message;
    // float32 rows: rounding ~1e-7 relative (6e-7 of 9.8 m/s^2 for the accel); the explicit
    // ROLL_90_PITCH_68_YAW_293 matrix has 6 decimals (1e-6 x 9.8).
    ExpectSensorFrame(*s, id == 38 ? 2e-6 : 1e-7, *ArduPilotRotationName(id));
    if (id != 0) {
      ASSERT_EQ(notes.size(), 1u);
      EXPECT_NE(notes[0].find(*ArduPilotRotationName(id)), std::string::npos) << notes[0];
    }
    // The table the fit reads is the same sensor frame.
    Result<FlightLogTable> t = FlightLogFromDataFlash(log, 0);
    ASSERT_TRUE(t.ok());
    EXPECT_NEAR(t->table.columns[2][150], Gyro(150)[1], 1e-7) << id;
  }
}

TEST(FlightLogFrames, RollOneEightyFlipsYAndZBackAsTempcalImuDoes) {
  // The reproduction: AHRS_ORIENTATION = 8 (ROLL_180) logs (x, -y, -z).
  const DataFlashContents log = Log(8, {});
  EXPECT_EQ(log.imus[0].gyr_y_rad_s[100], static_cast<double>(static_cast<float>(-Gyro(100)[1])));
  Result<FlightLogTable> t = FlightLogFromDataFlash(log, 0);
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->table.columns[2][100], static_cast<double>(static_cast<float>(Gyro(100)[1])));
  EXPECT_EQ(t->table.columns[3][100], static_cast<double>(static_cast<float>(Gyro(100)[2])));
}

TEST(FlightLogFrames, CustomAndUnknownOrientationsAreRefused) {
  for (float bad : {44.0f, 100.0f, 101.0f, 2.5f}) {
    DataFlashContents log = Log(0, {{"AHRS_ORIENTATION", bad}});
    Result<FlightLogTable> t = FlightLogFromDataFlash(log, 0);
    ASSERT_FALSE(t.ok()) << bad;
    EXPECT_EQ(t.error().kind, ErrorKind::kInvalidInput);
    EXPECT_NE(t.error().message.find("mem.bin: AHRS_ORIENTATION = "), std::string::npos) << t.error().message;
  }
}

// correct_sensor (AP_InertialSensor_tempcal.cpp): v -= p(clamp(T) - 35); v += p(clamp(Tcal) - 35),
// p(x) = (c1 + (c2 + c3 x) x) x 1e-6, evaluated here in float as on the vehicle.
float FirmwarePoly(const float c[3], float x) { return (c[0] + (c[1] + c[2] * x) * x) * x * 1.0e-6f; }

TEST(FlightLogFrames, TcalEnabledLogIsBroughtBackToTheRawSensor) {
  const float tmin = 15.0f, tmax = 50.0f, gyr_caltemp = 31.0f, acc_caltemp = 28.0f;
  // Coefficients [sensor][axis][order 1..3], scaled by 1e6.
  const float coeff[2][3][3] = {{{900.0f, 12.0f, -0.3f}, {-1500.0f, 4.0f, 0.2f}, {300.0f, -7.0f, 0.05f}},
                                {{15000.0f, 50.0f, -1.0f}, {-9000.0f, 20.0f, 0.5f}, {2000.0f, 90.0f, 0.0f}}};
  std::map<std::string, float> params = {{"INS_TCAL1_ENABLE", 1.0f}, {"INS_TCAL1_TMIN", tmin},
                                         {"INS_TCAL1_TMAX", tmax}, {"INS_GYR1_CALTEMP", gyr_caltemp},
                                         {"INS_ACC1_CALTEMP", acc_caltemp}};
  const char* kAxis[3] = {"X", "Y", "Z"};
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) {
      params["INS_TCAL1_GYR" + std::to_string(k + 1) + "_" + kAxis[a]] = coeff[0][a][k];
      params["INS_TCAL1_ACC" + std::to_string(k + 1) + "_" + kAxis[a]] = coeff[1][a][k];
    }
  auto correct = [&](int sensor, int i, std::array<double, 3> v) {
    const float t = std::clamp(static_cast<float>(TempC(i)), tmin, tmax);
    const float tc = std::clamp(sensor == 0 ? gyr_caltemp : acc_caltemp, tmin, tmax);
    for (int a = 0; a < 3; ++a)
      v[a] = v[a] - FirmwarePoly(coeff[sensor][a], t - 35.0f) + FirmwarePoly(coeff[sensor][a], tc - 35.0f);
    return v;
  };
  for (int orientation : {0, 8, 17}) {
    const DataFlashContents log = Log(orientation, params, correct);
    std::vector<std::string> notes;
    Result<DataFlashImuSeries> s = DataFlashImuToSensorFrame(log, log.imus[0], &notes);
    ASSERT_TRUE(s.ok()) << s.error().message;
    ExpectSensorFrame(*s, 2e-7, "orientation " + std::to_string(orientation));
    EXPECT_NE(notes.back().find("INS_TCAL1_ENABLE = 1"), std::string::npos);
    // Without the undo the rows differ from the sensor by the correction (so the test can fail).
    if (orientation == 0) {
      EXPECT_GT(std::abs(log.imus[0].gyr_x_rad_s[0] - Gyro(0)[0]), 1e-3);
    }
  }
  // ENABLE = 2 (learning): the firmware corrects nothing, the rows are raw and kept.
  params["INS_TCAL1_ENABLE"] = 2.0f;
  const DataFlashContents learn = Log(0, params);
  std::vector<std::string> notes;
  Result<DataFlashImuSeries> s = DataFlashImuToSensorFrame(learn, learn.imus[0], &notes);
  ASSERT_TRUE(s.ok());
  ExpectSensorFrame(*s, 1e-7, "learning");
  params["INS_TCAL1_ENABLE"] = 3.0f;
  const DataFlashContents bad = Log(0, params);
  EXPECT_FALSE(DataFlashImuToSensorFrame(bad, bad.imus[0], &notes).ok());
}

TEST(FlightLogFrames, EncodedLogRoundTripsWithAccel) {
  const DataFlashContents log = Log(0, {{"INS_TCAL2_ENABLE", 0.0f}});
  ASSERT_EQ(log.imus.size(), 1u);
  EXPECT_EQ(log.parameters.at("INS_TCAL2_ENABLE"), 0.0);
  EXPECT_EQ(log.imus[0].acc_z_m_s2[3], static_cast<double>(static_cast<float>(Accel(3)[2])));
  EXPECT_EQ(log.imus[0].temp_c[3], static_cast<double>(static_cast<float>(TempC(3))));
  EXPECT_EQ(log.message_counts.at("IMU"), static_cast<std::size_t>(kFrameRows));
}

}  // namespace
}  // namespace gyrocomp

namespace gyrocomp {
namespace {

TEST(FlightLogFrames, CompensationChangedMidLogKeepsTheRowsBefore) {
  // A learning run: INS_TCAL1_ENABLE = 2 (rows raw), then 1 with coefficients: tempcal_IMU.py
  // stops capturing there; so does the reader, and it undoes nothing for the rows before.
  DataFlashWriteInput in;
  in.parameters["INS_TCAL1_ENABLE"] = 2.0f;
  DataFlashImuWriteInput imu;
  for (int i = 0; i < 10; ++i) {
    imu.time_us.push_back(1000 + 1000 * static_cast<std::uint64_t>(i));
    imu.gyr_x_rad_s.push_back(0.01f * static_cast<float>(i));
    imu.gyr_y_rad_s.push_back(0.0f);
    imu.gyr_z_rad_s.push_back(0.0f);
    imu.temp_c.push_back(30.0f + static_cast<float>(i));
  }
  in.imus.push_back(imu);
  Result<std::string> bytes = EncodeDataFlash(in);
  ASSERT_TRUE(bytes.ok());
  // Append PARM records (type 64, "QNff") at TimeUS 6500: ENABLE -> 1, a coefficient, then 4 more rows.
  auto parm = [](const std::string& n, float v) {
    std::string r("\xA3\x95\x40", 3);
    const std::uint64_t t = 6500;
    r.append(reinterpret_cast<const char*>(&t), 8);
    std::string name = n;
    name.resize(16, '\0');
    r += name;
    r.append(reinterpret_cast<const char*>(&v), 4);
    r.append(reinterpret_cast<const char*>(&v), 4);
    return r;
  };
  const std::string all = *bytes + parm("INS_TCAL1_ENABLE", 1.0f) + parm("INS_TCAL1_GYR1_X", 5000.0f);
  Result<DataFlashContents> log = ParseDataFlash(reinterpret_cast<const std::uint8_t*>(all.data()), all.size(), "mid.bin");
  ASSERT_TRUE(log.ok()) << log.error().message;
  ASSERT_EQ(log->parameters_changed_during_imu.count("INS_TCAL1_ENABLE"), 1u);
  EXPECT_EQ(log->parameters_changed_during_imu.at("INS_TCAL1_ENABLE").time_us, 6500u);
  std::vector<std::string> notes;
  Result<DataFlashImuSeries> s = DataFlashImuToSensorFrame(*log, log->imus[0], &notes);
  ASSERT_TRUE(s.ok()) << s.error().message;
  ASSERT_EQ(s->time_us.size(), 6u);  // rows at 1000..6000 us
  EXPECT_EQ(s->gyr_x_rad_s[5], static_cast<double>(0.01f * 5.0f));  // ENABLE was 2 then: raw, nothing undone
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes[0].find("mid.bin: byte " + std::to_string(bytes->size()) + ": INS_TCAL1_ENABLE changes from 2 to 1"),
            std::string::npos)
      << notes[0];
}

}  // namespace
}  // namespace gyrocomp

namespace gyrocomp {
namespace {

TEST(FlightLogFrames, AverageWindowKeepsOneMeanRowPerWindowAndRotatesTheSame) {
  DataFlashWriteInput in;
  in.parameters["AHRS_ORIENTATION"] = 8.0f;
  DataFlashImuWriteInput imu;
  for (int i = 0; i < 200; ++i) {  // 100 Hz for 2 s from t = 1 s
    imu.time_us.push_back(1000000 + 10000 * static_cast<std::uint64_t>(i));
    imu.gyr_x_rad_s.push_back(static_cast<float>(i));
    imu.gyr_y_rad_s.push_back(2.0f);
    imu.gyr_z_rad_s.push_back(-1.0f);
    imu.acc_x_m_s2.push_back(0.5f);
    imu.acc_y_m_s2.push_back(0.0f);
    imu.acc_z_m_s2.push_back(9.80665f);
    imu.temp_c.push_back(20.0f + 0.01f * static_cast<float>(i));
  }
  in.imus.push_back(imu);
  Result<std::string> bytes = EncodeDataFlash(in);
  ASSERT_TRUE(bytes.ok());
  DataFlashReadOptions o;
  o.average_window_us = 500000;
  Result<DataFlashContents> log = ParseDataFlash(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size(), "w.bin", o);
  ASSERT_TRUE(log.ok()) << log.error().message;
  ASSERT_EQ(log->imus[0].time_us.size(), 4u);  // 50 rows per 0.5 s window
  EXPECT_EQ(log->imus[0].gyr_x_rad_s[1], 74.5);
  EXPECT_EQ(log->imus[0].time_us[0], 1245000u);
  std::vector<std::string> notes;
  Result<DataFlashImuSeries> s = DataFlashImuToSensorFrame(*log, log->imus[0], &notes);
  ASSERT_TRUE(s.ok());
  EXPECT_NEAR(s->gyr_y_rad_s[2], -2.0, 1e-12);  // ROLL_180 undone on the means
  EXPECT_NEAR(s->acc_z_m_s2[3], -9.80665, 1e-5);
}

}  // namespace
}  // namespace gyrocomp
