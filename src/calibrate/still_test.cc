// DetectStill on simulated ordinary flights (gyrocomp/sim/flight.h): power-on at ambients over
// 0..35 C, 1..10 min still while self-heating, 5..20 min of flight with manoeuvres, vibration and
// airflow cooling, landing, minutes still; a per-power-on offset of 0.05 deg/s per gyro axis and
// 20 mg per accel axis. Checked: no sample of motion is used, >= 90 % of the true still time is
// used, with and without the log's armed and landed state; a state that says "disarmed, landed"
// throughout does not admit the motion the IMU shows.
#include "gyrocomp/calibrate/still.h"

#include <cstdio>

#include <gtest/gtest.h>

#include "gyrocomp/sim/flight.h"

namespace gyrocomp {
namespace {

struct Score {
  std::size_t motion_used = 0;
  double still_true_s = 0.0, still_used_s = 0.0;
};

Score ScoreOf(const FlightRun& run, const StillDetection& d, double fs) {
  Score s;
  for (std::size_t i = 0; i < run.time_s.size(); ++i) {
    if (d.still[i] && !run.truly_still[i]) ++s.motion_used;
    if (run.truly_still[i]) s.still_true_s += 1.0 / fs;
    if (run.truly_still[i] && d.still[i]) s.still_used_s += 1.0 / fs;
  }
  return s;
}

TEST(DetectStill, OrdinaryFlightsNoMotionUsedAndNinetyPercentOfStillTime) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    FlightSimOptions o;
    o.seed = seed;
    o.ambient_c = 35.0 * static_cast<double>(seed - 1) / 5.0;  // 0, 7, 14, 21, 28, 35 C
    o.still_before_s = 60.0 + 108.0 * static_cast<double>(seed - 1);  // 1 .. 10 min
    o.flight_s = 300.0 + 180.0 * static_cast<double>(seed - 1);       // 5 .. 20 min
    o.still_after_s = 120.0 + 30.0 * static_cast<double>(seed % 3);
    Result<FlightRun> run = SimulateFlight(o);
    ASSERT_TRUE(run.ok()) << run.error().message;
    std::vector<bool> in_air(run->landed.size());
    for (std::size_t i = 0; i < in_air.size(); ++i) in_air[i] = !run->landed[i];
    for (bool with_armed : {true, false}) {
      Result<StillDetection> d = DetectStill(run->time_s, run->gyro_rad_s, run->accel_m_s2, run->temp_c,
                                             with_armed ? StillLogState{run->armed, in_air} : StillLogState{});
      ASSERT_TRUE(d.ok()) << d.error().message;
      const Score s = ScoreOf(*run, *d, o.fs_hz);
      std::printf("seed %d armed / landed state %s: still used %.1f of %.1f s (%.1f %%), motion samples used %zu\n",
                  static_cast<int>(seed), with_armed ? "given" : "unknown", s.still_used_s, s.still_true_s,
                  100.0 * s.still_used_s / s.still_true_s, s.motion_used);
      EXPECT_EQ(s.motion_used, 0u) << d->BriefReport();
      EXPECT_GE(s.still_used_s, 0.9 * s.still_true_s) << d->BriefReport();
      ASSERT_EQ(d->segments.size(), 2u) << d->BriefReport();  // before take-off, after landing
      EXPECT_GT(d->segments[0].temp_max_c - d->segments[0].temp_min_c, 0.0);
      ASSERT_FALSE(d->rejected.empty());
      EXPECT_NE(d->rejected[0].reason.find(with_armed ? "armed" : "motion"), std::string::npos) << d->rejected[0].reason;
      if (with_armed) {
        EXPECT_NE(d->rejected[0].reason.find("in the air (log's landed state)"), std::string::npos) << d->rejected[0].reason;
      }
    }
  }
}

TEST(DetectStill, TheLogsStateNeverAdmitsMotionTheImuShows) {
  FlightSimOptions o;
  o.seed = 3;
  o.still_before_s = 200.0;
  o.flight_s = 300.0;
  Result<FlightRun> run = SimulateFlight(o);
  ASSERT_TRUE(run.ok()) << run.error().message;
  // A log whose state is wrong: disarmed and landed throughout.
  const StillLogState wrong{std::vector<bool>(run->time_s.size(), false), std::vector<bool>(run->time_s.size(), false)};
  Result<StillDetection> d = DetectStill(run->time_s, run->gyro_rad_s, run->accel_m_s2, run->temp_c, wrong);
  ASSERT_TRUE(d.ok()) << d.error().message;
  const Score s = ScoreOf(*run, *d, o.fs_hz);
  EXPECT_EQ(s.motion_used, 0u) << d->BriefReport();
  EXPECT_GE(s.still_used_s, 0.9 * s.still_true_s) << d->BriefReport();
  for (const RejectedPart& p : d->rejected) {
    EXPECT_EQ(p.reason.find("armed"), std::string::npos) << p.reason;
  }
}

// Motors that barely shake the board (vibration at the noise level): armed on the ground looks
// still to the IMU, which alone uses those rows; the log's armed state keeps them out.
TEST(DetectStill, TheArmedStateKeepsOutWhatTheImuCannotSee) {
  FlightSimOptions o;
  o.seed = 4;
  o.still_before_s = 200.0;
  o.armed_ground_s = 60.0;  // a minute armed on the ground before take-off
  o.flight_s = 300.0;
  o.landed_armed_s = 60.0;
  o.vibration_gyro_dps = 0.0, o.vibration_accel_m_s2 = 0.0;
  Result<FlightRun> run = SimulateFlight(o);
  ASSERT_TRUE(run.ok()) << run.error().message;
  std::vector<bool> in_air(run->landed.size());
  for (std::size_t i = 0; i < in_air.size(); ++i) in_air[i] = !run->landed[i];
  Result<StillDetection> imu_alone = DetectStill(run->time_s, run->gyro_rad_s, run->accel_m_s2, run->temp_c, {});
  Result<StillDetection> with_state =
      DetectStill(run->time_s, run->gyro_rad_s, run->accel_m_s2, run->temp_c, StillLogState{run->armed, in_air});
  ASSERT_TRUE(imu_alone.ok() && with_state.ok());
  const Score a = ScoreOf(*run, *imu_alone, o.fs_hz), b = ScoreOf(*run, *with_state, o.fs_hz);
  std::printf("armed rows used: IMU alone %zu, with the log's state %zu\n", a.motion_used, b.motion_used);
  EXPECT_GT(a.motion_used, static_cast<std::size_t>(30.0 * o.fs_hz)) << imu_alone->BriefReport();  // the test's premise
  EXPECT_EQ(b.motion_used, 0u) << with_state->BriefReport();
  EXPECT_GE(b.still_used_s, 0.9 * b.still_true_s) << with_state->BriefReport();
}

TEST(DetectStill, StateVectorsOfTheWrongLengthAreAnError) {
  const std::vector<double> t = {0.0, 1.0, 2.0};
  const std::array<std::vector<double>, 3> z = {std::vector<double>(3, 0.0), std::vector<double>(3, 0.0), std::vector<double>(3, 0.0)};
  Result<StillDetection> d = DetectStill(t, z, z, {}, StillLogState{{}, {true}});
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("state.in_air"), std::string::npos) << d.error().message;
}

TEST(DetectStill, AChamberRunIsStillThroughout) {
  FlightSimOptions o;
  o.still_before_s = 1200.0;
  o.armed_ground_s = o.flight_s = o.landed_armed_s = o.still_after_s = 0.0;
  Result<FlightRun> run = SimulateFlight(o);
  ASSERT_TRUE(run.ok());
  Result<StillDetection> d = DetectStill(run->time_s, run->gyro_rad_s, run->accel_m_s2, run->temp_c, {});
  ASSERT_TRUE(d.ok());
  ASSERT_EQ(d->segments.size(), 1u) << d->BriefReport();
  EXPECT_GE(d->still_s, 0.99 * d->total_s) << d->BriefReport();
}

TEST(DetectStill, ASlowSteadyTurnIsNotStill) {
  // 5 deg/s about z for a minute in the middle of 5 still minutes: no variance, a mean rate.
  FlightSimOptions o;
  o.still_before_s = 300.0;
  o.armed_ground_s = o.flight_s = o.landed_armed_s = o.still_after_s = 0.0;
  Result<FlightRun> run = SimulateFlight(o);
  ASSERT_TRUE(run.ok());
  for (std::size_t i = 0; i < run->time_s.size(); ++i)
    if (run->time_s[i] >= 120.0 && run->time_s[i] < 180.0) run->gyro_rad_s[2][i] += 5.0 * 3.14159265358979 / 180.0;
  Result<StillDetection> d = DetectStill(run->time_s, run->gyro_rad_s, run->accel_m_s2, run->temp_c, {});
  ASSERT_TRUE(d.ok());
  for (std::size_t i = 0; i < run->time_s.size(); ++i) {
    if (run->time_s[i] >= 120.0 && run->time_s[i] < 180.0) {
      ASSERT_FALSE(d->still[i]) << run->time_s[i];
    }
  }
  ASSERT_EQ(d->rejected.size(), 1u);
  EXPECT_NE(d->rejected[0].reason.find("turning"), std::string::npos) << d->rejected[0].reason;
}

TEST(StillDetectorOptions, OutOfRangeNamesTheField) {
  StillDetectorOptions o;
  std::string why;
  EXPECT_TRUE(o.IsValid(&why));
  o.window_s = 0.0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("StillDetectorOptions::window_s"), std::string::npos) << why;
}

}  // namespace
}  // namespace gyrocomp
