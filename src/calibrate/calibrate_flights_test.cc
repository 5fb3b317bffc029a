// The calibrate stage on logs in which the vehicle moves, pooled (chamber runs pooled:
// calibrate_two_runs_test.cc):
// - ten simulated flights of one board (ambients 0..35 C, per-power-on offsets of 0.05 deg/s and
//   20 mg per axis, landing at another attitude) recover the true gyro and accelerometer curves;
// - three short flights at one ambient do not identify the curve: no parameter entry, the reason
//   and which log would help;
// - the simulated flight ULogs carry the armed / landed state as PX4's topics, a DataFlash flight
//   as ARM records and EV events: no still row is armed or in the air, and >= 90 % of the true
//   still time is used (with the state ignored, both tests fail: the DataFlash flight's motors
//   barely shake the board and the IMU alone uses 11600 armed rows);
// - what is not refused between logs of one board, with a note naming both files and values: a
//   board rotation (ArduPilot AHRS_ORIENTATION; the reader rotates each log back with its own
//   value, so the pooled parameters are those of the unrotated logs) and a log rate (a flight
//   logged at half the rate: the pooled curve as with every log at the full rate).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <utility>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "gyrocomp/calibrate/calibrate.h"
#include "gyrocomp/calibrate/pooled_fit.h"
#include "gyrocomp/core/units.h"
#include "gyrocomp/io/dataflash.h"
#include "gyrocomp/io/ulog.h"
#include "gyrocomp/sim/flight.h"
#include "gyrocomp/sim/simulator.h"
#include "calibrate_test_helpers.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

using namespace calibrate_test;

// One IMU of one board in an ordinary flight with the given curve (FlightSimOptions).
FlightSimOptions Flight(int n, double ambient_c, double still_before_s, double still_after_s) {
  FlightSimOptions o;
  o.fs_hz = 100.0;
  o.seed = 100 + static_cast<std::uint64_t>(n);
  o.ambient_c = ambient_c;
  o.still_before_s = still_before_s;
  o.flight_s = 300.0 + 60.0 * (n % 4);
  o.still_after_s = still_after_s;
  o.gyro_drift_dps = {0.0, 4e-3, 2e-4, -4e-6};
  o.accel_drift_m_s2 = {0.0, 2e-3, 1e-4, -2e-6};
  return o;
}

std::string WriteFlight(const testing::TempDir& dir, const FlightSimOptions& o, int n) {
  Result<FlightRun> run = SimulateFlight(o);
  EXPECT_TRUE(run.ok()) << run.error().message;
  Result<std::string> bytes = EncodeFlightULog({*run});
  EXPECT_TRUE(bytes.ok()) << bytes.error().message;
  return testing::WriteFile(dir / ("flight" + std::to_string(n) + ".ulg"), *bytes);
}

TEST(CalibrateFlights, TenFlightsWithPowerOnOffsetsRecoverTheTrueCurve) {
  testing::TempDir dir("calibrate_flights_test");
  std::vector<std::string> logs;
  FlightSimOptions truth;
  for (int n = 0; n < 10; ++n) {
    truth = Flight(n, 35.0 * n / 9.0, 120.0 + 50.0 * n, 240.0);
    logs.push_back(WriteFlight(dir, truth, n));
  }
  Result<CalibrateResult> r = CalibrateLogs(logs, CalibrateOptions{});
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->logs.size(), 10u);
  double detected_s = 0.0;
  for (const CalibrateResult::LogStill& l : r->logs) {
    EXPECT_EQ(l.detection.segments.size(), 2u) << l.detection.BriefReport();
    detected_s += l.detection.still_s;
  }
  for (const CalibratedSensor& s : r->sensors) {
    ASSERT_TRUE(s.calibrated()) << s.type << ": " << s.reason << "; " << s.identification.statement;
    EXPECT_EQ(s.fit, "pooled");
    EXPECT_EQ(s.identification.logs_with_still, 10);
    // The fit's rows stand for the still time found (a segment's last partial second dropped).
    EXPECT_NEAR(s.identification.still_s, detected_s, 0.01 * detected_s);
    EXPECT_GT(s.identification.overlap_c, 10.0);
    std::vector<double> temps;
    for (double t = s.temp_min_c; t <= s.temp_max_c; t += 0.25) temps.push_back(t);
    for (int k = 0; k < 3; ++k) {
      auto true_curve = [&](double t) {
        return s.type == "gyro" ? FlightGyroDriftRadS(truth, k, t) : FlightAccelDriftM_S2(truth, k, t);
      };
      const double error = RmsAfterOffset(temps, [&](double t) { return s.cubics[k].Evaluate(t); }, true_curve);
      const double drift = RmsAfterOffset(temps, [](double) { return 0.0; }, true_curve);
      std::printf("%s axis %d over %.1f..%.1f C: curve error %.3g, curve_sd %.3g, drift %.3g (%s)\n", s.type.c_str(), k,
                  s.temp_min_c, s.temp_max_c, error, s.curve_sd[static_cast<std::size_t>(k)], drift, s.unit.c_str());
      // The per-power-on offsets (0.05 deg/s, 20 mg 1 sigma) are of the drift's size; the pooled
      // fit leaves a twentieth of the drift.
      EXPECT_LT(error, 0.05 * drift) << s.type << " axis " << k;
    }
  }
  EXPECT_NE(r->parameter_text.find("TC_G0_X1_0"), std::string::npos);
  EXPECT_NE(r->parameter_text.find("TC_A0_X1_0"), std::string::npos);
}

TEST(CalibrateFlights, ThreeShortFlightsAtOneAmbientAreRefusedWithWhatWouldHelp) {
  testing::TempDir dir("calibrate_flights_test");
  std::vector<std::string> logs;
  for (int n = 0; n < 3; ++n) {
    FlightSimOptions o = Flight(n, 20.0, 60.0, 60.0);
    o.self_heating_tau_s = 2000.0;  // a slow board: a few degrees per minute of standing still
    logs.push_back(WriteFlight(dir, o, n));
  }
  Result<CalibrateResult> r = CalibrateLogs(logs, CalibrateOptions{});
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_FALSE(r->AnyCalibrated());
  EXPECT_TRUE(r->parameter_text.empty());
  for (const CalibratedSensor& s : r->sensors) {
    EXPECT_FALSE(s.calibrated());
    EXPECT_EQ(s.identification.logs_with_still, 3);
    EXPECT_NE(s.reason.find(" < "), std::string::npos) << s.reason;
    EXPECT_NE(s.identification.would_help.find("C"), std::string::npos) << s.identification.would_help;
    std::printf("%s: %s | %s | help: %s\n", s.type.c_str(), s.reason.c_str(), s.identification.statement.c_str(),
                s.identification.would_help.c_str());
  }
}

// Three flights written with their armed / landed state (actuator_armed, vehicle_status,
// vehicle_land_detected) read back by CalibrateLogs: the still segments hold no armed or in-air
// sample, the rejected parts say why, and >= 90 % of the true still time is used.
TEST(CalibrateFlights, TheLogsArmedAndLandedStateKeepsEveryStillRowOnTheGround) {
  testing::TempDir dir("calibrate_flights_test");
  std::vector<std::string> logs;
  std::vector<FlightRun> truth;
  for (int n = 0; n < 3; ++n) {
    FlightSimOptions o = Flight(n, 10.0 * n, 120.0 + 60.0 * n, 200.0);
    Result<FlightRun> run = SimulateFlight(o);
    ASSERT_TRUE(run.ok()) << run.error().message;
    truth.push_back(*run);
    logs.push_back(testing::WriteFile(dir / ("flight" + std::to_string(n) + ".ulg"), *EncodeFlightULog({*run})));
  }
  Result<CalibrateResult> r = CalibrateLogs(logs, CalibrateOptions{});
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->logs.size(), 3u);
  for (std::size_t n = 0; n < 3; ++n) {
    const CalibrateResult::LogStill& l = r->logs[n];
    EXPECT_NE(l.state.find("armed: actuator_armed.armed, vehicle_status.arming_state from 1.00 s"), std::string::npos) << l.state;
    EXPECT_NE(l.state.find("landed: vehicle_land_detected.landed"), std::string::npos) << l.state;
    const FlightRun& run = truth[n];
    double still_true_s = 0.0, still_used_s = 0.0;
    std::size_t armed_used = 0, in_air_used = 0;
    for (std::size_t i = 0; i < run.time_s.size(); ++i) {
      const double t = run.time_s[i] + 1.0;  // EncodeFlightULog: logging starts at 1 s
      bool used = false;
      for (const StillSegment& seg : l.detection.segments) used = used || (t >= seg.start_s && t < seg.start_s + seg.length_s);
      armed_used += used && run.armed[i];
      in_air_used += used && !run.landed[i];
      still_true_s += run.truly_still[i] ? 1.0 / 100.0 : 0.0;
      still_used_s += run.truly_still[i] && used ? 1.0 / 100.0 : 0.0;
    }
    std::printf("flight %zu: still used %.1f of %.1f s (%.1f %%); %s\n", n, still_used_s, still_true_s,
                100.0 * still_used_s / still_true_s, l.detection.BriefReport().c_str());
    EXPECT_EQ(armed_used, 0u) << l.detection.BriefReport();
    EXPECT_EQ(in_air_used, 0u) << l.detection.BriefReport();
    EXPECT_GE(still_used_s, 0.9 * still_true_s) << l.detection.BriefReport();
    std::string reasons;
    for (const RejectedPart& p : l.detection.rejected) reasons += p.reason + " | ";
    EXPECT_NE(reasons.find("armed"), std::string::npos) << reasons;
    EXPECT_NE(reasons.find("in the air (log's landed state)"), std::string::npos) << reasons;
  }
}

// The same through an ArduPilot DataFlash log: a flight whose motors barely shake the board (a
// minute armed on the ground before take-off and after landing, vibration 0), its state as ARM
// records and EV events (10 ARMED / 11 DISARMED, 28 NOT_LANDED / 18 LAND_COMPLETE). The IMU alone
// would take the armed minutes for still; the log's state keeps every armed row out.
TEST(CalibrateFlights, ADataFlashLogsArmAndEventRecordsKeepTheArmedRowsOut) {
  testing::TempDir dir("calibrate_flights_test");
  FlightSimOptions o = Flight(0, 15.0, 200.0, 200.0);
  o.armed_ground_s = o.landed_armed_s = 60.0;
  o.vibration_gyro_dps = o.vibration_accel_m_s2 = 0.0;
  Result<FlightRun> run = SimulateFlight(o);
  ASSERT_TRUE(run.ok()) << run.error().message;
  DataFlashWriteInput in;
  DataFlashImuWriteInput imu;
  auto us = [&](std::size_t i) { return static_cast<std::uint64_t>(std::llround(run->time_s[i] * 1e6)) + 1000000; };
  for (std::size_t i = 0; i < run->time_s.size(); ++i) {
    imu.time_us.push_back(us(i));
    imu.gyr_x_rad_s.push_back(static_cast<float>(run->gyro_rad_s[0][i]));
    imu.gyr_y_rad_s.push_back(static_cast<float>(run->gyro_rad_s[1][i]));
    imu.gyr_z_rad_s.push_back(static_cast<float>(run->gyro_rad_s[2][i]));
    imu.acc_x_m_s2.push_back(static_cast<float>(run->accel_m_s2[0][i]));
    imu.acc_y_m_s2.push_back(static_cast<float>(run->accel_m_s2[1][i]));
    imu.acc_z_m_s2.push_back(static_cast<float>(run->accel_m_s2[2][i]));
    imu.temp_c.push_back(static_cast<float>(run->temp_c[i]));
    if (i == 0 || run->armed[i] != run->armed[i - 1]) {
      in.arm_states.push_back({us(i), run->armed[i] ? 1 : 0});
      if (i > 0) in.events.push_back({us(i), run->armed[i] ? 10 : 11});
    }
    if (i > 0 && run->landed[i] != run->landed[i - 1]) in.events.push_back({us(i), run->landed[i] ? 18 : 28});
  }
  in.imus.push_back(std::move(imu));
  const std::string log = testing::WriteFile(dir / "flight.bin", *EncodeDataFlash(in));
  CalibrateOptions co;
  co.format = "ardupilot";
  Result<CalibrateResult> r = CalibrateLogs({log}, co);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const CalibrateResult::LogStill& l = r->logs.at(0);
  EXPECT_NE(l.state.find("armed: ARM.ArmState, EV ARMED / DISARMED from 1.00 s"), std::string::npos) << l.state;
  EXPECT_NE(l.state.find("landed: EV LAND_COMPLETE / NOT_LANDED"), std::string::npos) << l.state;
  std::size_t armed_used = 0;
  double still_true_s = 0.0, still_used_s = 0.0;
  for (std::size_t i = 0; i < run->time_s.size(); ++i) {
    const double t = run->time_s[i] + 1.0;
    bool used = false;
    for (const StillSegment& seg : l.detection.segments) used = used || (t >= seg.start_s && t < seg.start_s + seg.length_s);
    armed_used += used && run->armed[i];
    still_true_s += run->truly_still[i] ? 0.01 : 0.0;
    still_used_s += run->truly_still[i] && used ? 0.01 : 0.0;
  }
  std::printf("DataFlash flight: armed rows used %zu, still used %.1f of %.1f s; %s\n", armed_used, still_used_s, still_true_s,
              l.detection.BriefReport().c_str());
  EXPECT_EQ(armed_used, 0u) << l.detection.BriefReport();
  EXPECT_GE(still_used_s, 0.9 * still_true_s) << l.detection.BriefReport();
}

// The largest |a(T) - b(T)| over the range of a, for every axis.
double LargestDifference(const CalibratedSensor& a, const CalibratedSensor& b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.cubics.size(); ++k)
    for (double t = a.temp_min_c; t <= a.temp_max_c; t += 0.5) worst = std::max(worst, std::abs(a.cubics[k].Evaluate(t) - b.cubics[k].Evaluate(t)));
  return worst;
}
// The largest change of a's cubics over its range (the drift's size), every axis.
double LargestDrift(const CalibratedSensor& a) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.cubics.size(); ++k)
    for (double t = a.temp_min_c; t <= a.temp_max_c; t += 0.5)
      worst = std::max(worst, std::abs(a.cubics[k].Evaluate(t) - a.cubics[k].Evaluate(a.temp_min_c)));
  return worst;
}

// Two chamber runs of one board as ArduPilot logs, the second logged once with AHRS_ORIENTATION 0
// and once with 1 (yaw 45): not refused, a note names both files and values, and the pooled
// parameters are those of the unrotated pair (the reader rotates each log back with its own
// value; were it not, x and y would mix and the curves differ by the drift's size).
TEST(CalibrateFlights, ABoardRotationChangeBetweenLogsIsUndoneAndNoted) {
  testing::TempDir dir("calibrate_flights_test");
  const BoardRun a = Chamber(ThermalProfileKind::kRamp, 51), b = Chamber(ThermalProfileKind::kPaper, 52);
  CalibrateOptions o;
  o.format = "ardupilot";
  // The cubic alone: with the dT/dt gain (the default) the two pairs' gyro x, y and accel x
  // curves differ by up to 19 % of the drift, because on chamber runs whose heating rate is nearly
  // constant inside each log the gain is all but collinear with the log's constant and the float32
  // rounding of the rotated rows decides it; that is the pooled fit's, not the rotation's.
  o.pooled_dtemp = false;
  const std::string a0 = testing::WriteFile(dir / "a0.bin", *EncodeBoardDataFlash(a, a.fs_hz, 0));
  const std::string b0 = testing::WriteFile(dir / "b0.bin", *EncodeBoardDataFlash(b, b.fs_hz, 0));
  const std::string b1 = testing::WriteFile(dir / "b1.bin", *EncodeBoardDataFlash(b, b.fs_hz, 1));
  Result<CalibrateResult> same = CalibrateLogs({a0, b0}, o), rotated = CalibrateLogs({a0, b1}, o);
  ASSERT_TRUE(same.ok()) << same.error().message;
  ASSERT_TRUE(rotated.ok()) << rotated.error().message;
  std::string notes;
  for (const std::string& n : rotated->notes) notes += n + "\n";
  EXPECT_NE(notes.find("AHRS_ORIENTATION = 0 in " + a0 + ", 1 in " + b1 + ": pooled all the same"), std::string::npos) << notes;
  for (const std::string& n : same->notes) EXPECT_EQ(n.find("AHRS_ORIENTATION = 0 in"), std::string::npos) << n;
  ASSERT_EQ(same->sensors.size(), rotated->sensors.size());
  for (std::size_t i = 0; i < same->sensors.size(); ++i) {
    const CalibratedSensor &s = same->sensors[i], &t = rotated->sensors[i];
    ASSERT_TRUE(s.calibrated()) << s.reason;
    ASSERT_TRUE(t.calibrated()) << t.reason;
    EXPECT_EQ(s.fit, "pooled");
    const double diff = LargestDifference(s, t), drift = LargestDrift(s);
    std::printf("%s: rotated vs unrotated pair, largest difference %.3g of a drift of %.3g %s\n", s.type.c_str(), diff, drift,
                s.unit.c_str());
    // float32 rows rotated and rotated back: rounding only (measured 1.3e-9 and 6.5e-11 of the
    // drift for gyro and accel); axes mixed would differ by the drift's size.
    EXPECT_LT(diff, 1e-6 * drift) << s.type;
  }
}

// Four flights of one board, two of them logged at half the rate (50 Hz instead of 100 Hz): not
// refused, a note names the sensor, both files and both rates, and the pooled curves are those
// of the same four flights all logged at 100 Hz to within a small share of the drift (the still
// detector reads each log at its own noise level; the fit sees 1 s means either way).
TEST(CalibrateFlights, ALogRateChangeBetweenLogsIsPooledAndNoted) {
  testing::TempDir dir("calibrate_flights_test");
  std::vector<std::string> full, mixed;
  for (int n = 0; n < 4; ++n) {
    const FlightSimOptions o = Flight(n, 35.0 * n / 3.0, 300.0, 240.0);
    Result<FlightRun> run = SimulateFlight(o);
    ASSERT_TRUE(run.ok()) << run.error().message;
    full.push_back(testing::WriteFile(dir / ("full" + std::to_string(n) + ".ulg"), *EncodeFlightULog({*run})));
    mixed.push_back(n % 2 == 0 ? full.back()
                               : testing::WriteFile(dir / ("half" + std::to_string(n) + ".ulg"), *EncodeFlightULog({*run}, 2)));
  }
  Result<CalibrateResult> rf = CalibrateLogs(full, CalibrateOptions{}), rm = CalibrateLogs(mixed, CalibrateOptions{});
  ASSERT_TRUE(rf.ok()) << rf.error().message;
  ASSERT_TRUE(rm.ok()) << rm.error().message;
  std::string notes;
  for (const std::string& n : rm->notes) notes += n + "\n";
  EXPECT_NE(notes.find("gyro 0 (id " + std::to_string(BoardGyroDeviceId(0)) + "), accel 0 (id " +
                       std::to_string(BoardAccelDeviceId(0)) + "): logged at 100 Hz in " + mixed[0] + ", 50 Hz in " +
                       mixed[1] + ": pooled all the same"), std::string::npos) << notes;
  EXPECT_EQ(rm->notes.size(), 2u) << notes;  // one per half-rate log
  EXPECT_TRUE(rf->notes.empty()) << rf->notes.front();
  ASSERT_EQ(rf->sensors.size(), rm->sensors.size());
  for (std::size_t i = 0; i < rf->sensors.size(); ++i) {
    const CalibratedSensor &f = rf->sensors[i], &m = rm->sensors[i];
    ASSERT_TRUE(f.calibrated()) << f.reason << "; " << f.identification.statement;
    ASSERT_TRUE(m.calibrated()) << m.reason << "; " << m.identification.statement;
    EXPECT_NEAR(m.log_rate_hz, 100.0, 0.5);  // the first log's
    const double diff = LargestDifference(f, m), drift = LargestDrift(f);
    std::printf("%s: half-rate logs vs all at 100 Hz, largest difference %.3g of a drift of %.3g %s\n", f.type.c_str(), diff,
                drift, f.unit.c_str());
    // Half the rows: the block means' noise grows by sqrt(2), the still segments may move by a
    // window; measured 0.26 % (gyro) and 1.2 % (accel) of the drift; within 5 % of it, the bound
    // TenFlights puts on the error against the truth.
    EXPECT_LT(diff, 0.05 * drift) << f.type;
  }
}

// --optimise-for warm-up with a lag kept (temp_lag_s > 0): the cubic is the least-squares cubic
// over 401 temperatures of the steady curve at the lagged temperature T - s(T), s the heating
// state (T - T_lag while heating, CalibratedSensor::heating_state), expanded here directly
// (tolerance 1e-6 of the lag's effect: rounding of one linear solve each).
template <class Curve>
void ExpectWarmUpIsTheLaggedCurveAtTheHeatingState(const std::vector<std::string>& logs, const CalibratedSensor& steady,
                                                   const std::vector<std::pair<double, double>>& logged_and_lagged,
                                                   const Curve& curve) {
  CalibrateOptions o;
  o.optimise_for = "warm-up";
  Result<CalibrateResult> r = CalibrateLogs(logs, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const CalibratedSensor& g = r->sensors.front();
  ASSERT_EQ(g.temp_lag_s, steady.temp_lag_s);
  ASSERT_EQ(g.heating_state_kind, "lag_excess_c");
  const TemperatureCubic& c = steady.cubics[0];
  const auto lagged = [&](double t) {
    const double d = t - g.heating_state.At(t) - c.ref_temp_c;  // the lagged temperature - ref, unclamped
    return c.coeff[0] + d * (c.coeff[1] + d * (c.coeff[2] + d * c.coeff[3]));
  };
  double largest = 0.0;  // the lag's largest effect
  for (int i = 0; i <= 400; ++i) {
    const double t = c.temp_min_c + (c.temp_max_c - c.temp_min_c) * i / 400.0;
    largest = std::max(largest, std::abs(lagged(t) - c.Evaluate(t)));
  }
  ExpectLeastSquaresCubic(c, lagged, g.cubics[0], 1e-6 * largest, "lagged");
  std::vector<double> rows(logged_and_lagged.size());
  std::iota(rows.begin(), rows.end(), 0.0);
  const auto on_rows = [&](const TemperatureCubic& cubic) {
    return RmsAfterOffset(rows, [&](double i) { return cubic.Evaluate(logged_and_lagged[static_cast<std::size_t>(i)].first); },
                          [&](double i) { return curve(logged_and_lagged[static_cast<std::size_t>(i)].second); });
  };
  // Not a check: along these four warm-ups the warm-up cubic is no closer to the rows' drift than
  // the steady one (measured 8.38e-5 against 8.06e-5 rad/s): each 1 C bin is crossed early and
  // fast by one warm-up and late and slowly by another, and the median state fits neither.
  std::printf("along the warm-ups, drift - cubic RMS: warm-up %.3g, steady %.3g rad/s (heating state %s)\n",
              on_rows(g.cubics[0]), on_rows(c), g.heating_state_kind.c_str());
}

// Four warm-ups at ambients 5, 15, 25, 35 C (still throughout, 10 Hz, 20 min; the board rises
// 15 C with a 150 s time constant) whose gyro drift is a cubic of the temperature low-passed
// 60 s behind the logged one: the pooled fit finds a lag near it (the grid's 40..90 s) and its
// cubic is closer to the true curve than the fit on the logged temperature; with no lag in the
// data, none is kept.
TEST(CalibrateFlights, APooledLagIsFittedOnlyWhereTheCurveLagsTheLoggedTemperature) {
  const auto curve = [](double t) { const double d = t - 25.0; return (4e-3 * d + 1e-4 * d * d - 2e-6 * d * d * d) / units::kDegPerRad; };
  for (const double true_lag_s : {60.0, 0.0}) {
    testing::TempDir dir("calibrate_flights_test");
    std::vector<std::string> logs;
    std::vector<std::pair<double, double>> logged_and_lagged;  // every 10th row of every warm-up
    NormalGenerator rng(21);
    for (int n = 0; n < 4; ++n) {
      FlightRun r;
      const double fs = 10.0, ambient = 5.0 + 10.0 * n;
      double lagged = ambient;
      for (int i = 0; i < 12000; ++i) {
        const double t = i / fs, temp = ambient + 15.0 * (1.0 - std::exp(-t / 150.0));
        lagged = true_lag_s > 0.0 ? lagged + (temp - lagged) * (1.0 - std::exp(-1.0 / (fs * true_lag_s))) : temp;
        r.time_s.push_back(t), r.temp_c.push_back(temp);
        if (i % 10 == 0) logged_and_lagged.emplace_back(temp, lagged);
        const double offset = 0.05 / units::kDegPerRad * (n - 1.5);
        for (int a = 0; a < 3; ++a) r.gyro_rad_s[a].push_back(curve(lagged) * (1.0 + 0.2 * a) + offset + 5e-4 * rng.Next());
        for (int a = 0; a < 3; ++a) r.accel_m_s2[a].push_back((a == 2 ? -9.80665 : 0.0) + 0.02 * rng.Next());
        r.armed.push_back(false), r.landed.push_back(true), r.truly_still.push_back(true);
      }
      logs.push_back(testing::WriteFile(dir / ("warm" + std::to_string(n) + ".ulg"), *EncodeFlightULog({r})));
    }
    CalibrateOptions with_lag, without;
    without.pooled_lags_s.clear();
    Result<CalibrateResult> a = CalibrateLogs(logs, with_lag), b = CalibrateLogs(logs, without);
    ASSERT_TRUE(a.ok() && b.ok());
    const CalibratedSensor& ga = a->sensors.front();
    const CalibratedSensor& gb = b->sensors.front();
    ASSERT_EQ(ga.type, "gyro");
    ASSERT_TRUE(ga.calibrated() && gb.calibrated()) << ga.reason << gb.reason;
    std::vector<double> temps;
    for (double t = ga.temp_min_c; t <= ga.temp_max_c; t += 0.25) temps.push_back(t);
    const auto error = [&](const CalibratedSensor& s) {
      return RmsAfterOffset(temps, [&](double t) { return s.cubics[0].Evaluate(t); }, curve);
    };
    std::printf("true lag %g s: lag %g s (%s), error %.3g with, %.3g without (rad/s)\n", true_lag_s, ga.temp_lag_s,
                ga.lag_term.BriefReport().c_str(), error(ga), error(gb));
    if (true_lag_s > 0.0) {
      EXPECT_GE(ga.temp_lag_s, 40.0);
      EXPECT_LE(ga.temp_lag_s, 90.0);
      EXPECT_LT(error(ga), 0.5 * error(gb));  // the lag's share of the error removed, at least half of it
      ExpectWarmUpIsTheLaggedCurveAtTheHeatingState(logs, ga, logged_and_lagged, curve);
    } else {
      EXPECT_EQ(ga.temp_lag_s, 0.0) << ga.lag_term.BriefReport();
    }
    EXPECT_EQ(gb.temp_lag_s, 0.0);
  }
}

// EncodeFlightULog's enumeration order: multi_id k holds imus[order[k]] with that IMU's device
// ids; a list that is not a permutation is refused.
TEST(CalibrateFlights, EncodeFlightULogLogsEachIMUWithItsOwnDeviceIdInAnyOrder) {
  std::vector<FlightRun> imus(2);
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 20; ++i) {
      imus[k].time_s.push_back(0.1 * i), imus[k].temp_c.push_back(20.0 + k);
      for (int a = 0; a < 3; ++a) imus[k].gyro_rad_s[a].push_back(0.01 * (k + 1)), imus[k].accel_m_s2[a].push_back(k);
      imus[k].armed.push_back(false), imus[k].landed.push_back(true), imus[k].truly_still.push_back(true);
    }
  Result<std::string> bytes = EncodeFlightULog(imus, 1, {1, 0});
  ASSERT_TRUE(bytes.ok()) << bytes.error().message;
  Result<ULogContents> log = ParseULog(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size(), "order");
  ASSERT_TRUE(log.ok()) << log.error().message;
  ASSERT_EQ(log->gyros.size(), 2u);
  for (const ULogGyroSeries& g : log->gyros) {
    const int imu = g.multi_id == 0 ? 1 : 0;
    EXPECT_EQ(g.device_id, BoardGyroDeviceId(imu)) << g.multi_id;
    EXPECT_FLOAT_EQ(static_cast<float>(g.x_rad_s.front()), 0.01f * static_cast<float>(imu + 1)) << g.multi_id;
  }
  for (const ULogAccelSeries& acc : log->accels) EXPECT_EQ(acc.device_id, BoardAccelDeviceId(acc.multi_id == 0 ? 1 : 0));
  EXPECT_FALSE(EncodeFlightULog(imus, 1, {0, 0}).ok());
  EXPECT_FALSE(EncodeFlightULog(imus, 1, {0}).ok());
}

}  // namespace
}  // namespace gyrocomp
