// The armed / landed state of a flight log (gyrocomp/io/vehicle_state.h): PX4 ULog topics and
// ArduPilot DataFlash ARM / EV records written with the project's writers (PX4's and ArduPilot's
// field layouts), read back, merged and mapped onto sample times.
#include "gyrocomp/io/vehicle_state.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/io/dataflash.h"
#include "gyrocomp/io/ulog.h"

namespace gyrocomp {
namespace {

constexpr std::uint64_t kS = 1000000;  // us per s

// A one-row-per-second sensor_gyro from 1 s to 30 s, so the log has data besides the states.
ULogSensorWriteSeries Gyro() {
  ULogSensorWriteSeries g;
  g.topic = "sensor_gyro";
  for (std::uint64_t t = 1; t <= 30; ++t) {
    g.timestamp_us.push_back(t * kS);
    g.x.push_back(0.f), g.y.push_back(0.f), g.z.push_back(0.f), g.temperature_c.push_back(25.f);
  }
  return g;
}

ULogContents ParseBytes(const std::string& bytes, const ULogReadOptions& o = {}) {
  Result<ULogContents> log = ParseULog(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "t.ulg", o);
  EXPECT_TRUE(log.ok()) << log.error().message;
  return *log;
}

TEST(VehicleState, ULogTopicsAreReadAsChangesAndMerged) {
  ULogWriteInput in;
  in.series.push_back(Gyro());
  // actuator_armed: reported every 2 s, armed from 10 s to 20 s; vehicle_status (arming_state 2 =
  // armed) says armed from 9 s to 20 s; landed false (in the air) from 12 s to 18 s.
  ULogStateWriteSeries armed{"actuator_armed", {}, {}}, status{"vehicle_status", {}, {}}, land{"vehicle_land_detected", {}, {}};
  for (std::uint64_t t = 2; t <= 28; t += 2) armed.timestamp_us.push_back(t * kS), armed.value.push_back(t >= 10 && t < 20);
  for (std::uint64_t t : {3, 9, 20}) status.timestamp_us.push_back(t * kS), status.value.push_back(t == 9 ? 2 : 1);
  for (std::uint64_t t : {4, 12, 18}) land.timestamp_us.push_back(t * kS), land.value.push_back(t != 12);
  in.states = {armed, status, land};
  Result<std::string> bytes = EncodeULog(in);
  ASSERT_TRUE(bytes.ok()) << bytes.error().message;
  // The averaging of the sensors does not touch the states.
  ULogReadOptions o;
  o.average_window_us = 5 * kS;
  const ULogContents log = ParseBytes(*bytes, o);
  ASSERT_EQ(log.states.size(), 3u);
  EXPECT_EQ(log.states[0].topic, "actuator_armed");
  EXPECT_EQ(log.states[0].field, "armed");
  // Repeated values dropped: first row (2 s, 0), 10 s -> 1, 20 s -> 0.
  EXPECT_EQ(log.states[0].timestamp_us, (std::vector<std::uint64_t>{2 * kS, 10 * kS, 20 * kS}));
  EXPECT_EQ(log.states[0].value, (std::vector<int>{0, 1, 0}));
  EXPECT_EQ(log.states[1].value, (std::vector<int>{1, 2, 1}));

  const VehicleStateLog st = VehicleStateOfULog(log);
  EXPECT_EQ(st.armed_source, "actuator_armed.armed, vehicle_status.arming_state");
  EXPECT_EQ(st.landed_source, "vehicle_land_detected.landed");
  // Either source armed: from 9 s (vehicle_status) to 20 s.
  ASSERT_EQ(st.armed.size(), 3u);
  EXPECT_EQ(st.armed[1].time_us, 9 * kS);
  EXPECT_TRUE(st.armed[1].value);
  EXPECT_EQ(st.armed[2].time_us, 20 * kS);
  EXPECT_FALSE(st.armed[2].value);

  // Mapped onto times (s): before the first message the given default.
  const std::vector<double> t = {0.5, 2.0, 8.99, 9.0, 15.0, 19.999, 20.0, 29.0};
  EXPECT_EQ(StateAtTimes(st.armed, t, false), (std::vector<bool>{false, false, false, true, true, true, false, false}));
  EXPECT_EQ(StateAtTimes(st.armed, t, true), (std::vector<bool>{true, false, false, true, true, true, false, false}));
  EXPECT_EQ(StateAtTimes(st.landed, t, true), (std::vector<bool>{true, true, true, true, false, true, true, true}));
  EXPECT_EQ(StateAtTimes({}, t, true), std::vector<bool>(t.size(), true));
  EXPECT_NE(st.BriefReport().find("from 2.00 s"), std::string::npos) << st.BriefReport();
}

TEST(VehicleState, ULogWithoutStateTopicsSaysSo) {
  ULogWriteInput in;
  in.series.push_back(Gyro());
  const ULogContents log = ParseBytes(*EncodeULog(in));
  EXPECT_TRUE(log.states.empty());
  const VehicleStateLog st = VehicleStateOfULog(log);
  EXPECT_TRUE(st.armed.empty());
  EXPECT_TRUE(st.landed.empty());
  EXPECT_EQ(st.BriefReport(), "no armed or landed state in the log: the IMU alone decides");
}

// Damage: a state row whose size is wrong is skipped as the reader skips any damaged record (with
// the record before it, which no valid message follows), the rows after it kept.
TEST(VehicleState, ULogDamagedStateRowIsSkippedTheRestKept) {
  ULogWriteInput in;
  in.series.push_back(Gyro());
  ULogStateWriteSeries armed{"actuator_armed", {5 * kS, 10 * kS, 20 * kS, 25 * kS}, {0, 1, 1, 0}};
  in.states = {armed};
  std::string bytes = *EncodeULog(in);
  // The 'D' record of the armed row at 10 s: msg_id 1 (after the one sensor series), its payload
  // starts with the timestamp; give it two data bytes fewer (16 in the format, 15 without the
  // trailing _padding0 the spec lets a writer leave out).
  std::string ts(8, '\0');
  for (int i = 0; i < 8; ++i) ts[static_cast<std::size_t>(i)] = static_cast<char>(((10 * kS) >> (8 * i)) & 0xFF);
  const std::string row_head = std::string("\x12\x00" "D\x01\x00", 5) + ts;
  const auto at = bytes.find(row_head);
  ASSERT_NE(at, std::string::npos);
  bytes.erase(at + 5 + 8 + 1, 2);
  bytes[at] = '\x10';
  const ULogContents log = ParseBytes(bytes);
  ASSERT_EQ(log.damage.size(), 1u);
  EXPECT_EQ(log.damage[0].begin, at - 45);  // the sensor_gyro row at 10 s (45 bytes) goes with it
  ASSERT_EQ(log.states.size(), 1u);
  EXPECT_EQ(log.states[0].timestamp_us, (std::vector<std::uint64_t>{5 * kS, 20 * kS, 25 * kS}));
  EXPECT_EQ(log.states[0].value, (std::vector<int>{0, 1, 0}));
  ASSERT_EQ(log.gyros.size(), 1u);
  EXPECT_EQ(log.gyros[0].timestamp_us.size(), 29u);
}

DataFlashWriteInput DataFlashImu() {
  DataFlashWriteInput in;
  DataFlashImuWriteInput imu;
  for (std::uint64_t t = 1; t <= 30; ++t) {
    imu.time_us.push_back(t * kS);
    imu.gyr_x_rad_s.push_back(0.f), imu.gyr_y_rad_s.push_back(0.f), imu.gyr_z_rad_s.push_back(0.f);
    imu.temp_c.push_back(25.f);
  }
  in.imus.push_back(imu);
  return in;
}

TEST(VehicleState, DataFlashArmAndEventsAreMerged) {
  DataFlashWriteInput in = DataFlashImu();
  // ARM: armed 10 s .. 20 s. EV: ARMED at 9 s (an event a little earlier than ARM), DISARMED at
  // 20 s; NOT_LANDED at 12 s, LAND_COMPLETE_MAYBE at 17 s (no change), LAND_COMPLETE at 18 s.
  in.arm_states = {{10 * kS, 1}, {20 * kS, 0}};
  in.events = {{9 * kS, 10}, {12 * kS, 28}, {17 * kS, 17}, {18 * kS, 18}, {20 * kS, 11}};
  Result<std::string> bytes = EncodeDataFlash(in);
  ASSERT_TRUE(bytes.ok()) << bytes.error().message;
  DataFlashReadOptions o;
  o.average_window_us = 5 * kS;
  Result<DataFlashContents> log = ParseDataFlash(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size(), "t.bin", o);
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_EQ(log->arm_states.size(), 2u);
  EXPECT_EQ(log->events.size(), 5u);
  EXPECT_EQ(log->imus.at(0).records, 30u);
  const VehicleStateLog st = VehicleStateOfDataFlash(*log);
  EXPECT_EQ(st.armed_source, "ARM.ArmState, EV ARMED / DISARMED");
  EXPECT_EQ(st.landed_source, "EV LAND_COMPLETE / NOT_LANDED");
  const std::vector<double> t = {1.0, 9.0, 11.0, 12.0, 17.5, 18.0, 20.0, 25.0};
  EXPECT_EQ(StateAtTimes(st.armed, t, false), (std::vector<bool>{false, true, true, true, true, true, false, false}));
  // Landed unknown before 12 s (the first landed event): the default given.
  EXPECT_EQ(StateAtTimes(st.landed, t, true), (std::vector<bool>{true, true, true, false, false, true, true, true}));
}

TEST(VehicleState, DataFlashDamagedArmRecordIsSkippedTheRestKept) {
  DataFlashWriteInput in = DataFlashImu();
  in.arm_states = {{10 * kS, 1}, {20 * kS, 0}};
  std::string bytes = *EncodeDataFlash(in);
  // The first ARM record (type 66): its A3 95 header broken.
  const auto at = bytes.find(std::string("\xA3\x95\x42", 3), 5 * 89);  // after the five FMT records
  ASSERT_NE(at, std::string::npos);
  bytes[at] = '\x00';
  Result<DataFlashContents> log = ParseDataFlash(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "t.bin");
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_FALSE(log->damage.empty());
  ASSERT_EQ(log->arm_states.size(), 1u);
  EXPECT_EQ(log->arm_states[0].time_us, 20 * kS);
  EXPECT_EQ(log->imus.at(0).time_us.size(), 30u);
}

}  // namespace
}  // namespace gyrocomp
