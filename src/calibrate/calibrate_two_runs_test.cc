// The calibrate stage on chamber runs: a chamber run is still throughout and takes the single-run
// path (drift model + projection); two chamber runs of different profiles pooled: on held-out
// runs in both directions the pooled gyro cubic is never worse than the better single run's; the
// pooled file optimised for warm-up / both is the curve plus the gain times the heating state.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "gyrocomp/calibrate/calibrate.h"
#include "gyrocomp/calibrate/pooled_fit.h"
#include "gyrocomp/core/units.h"
#include "gyrocomp/io/ulog.h"
#include "gyrocomp/sim/simulator.h"
#include "calibrate_test_helpers.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

using namespace calibrate_test;

TEST(CalibrateFlights, AChamberRunIsStillThroughoutAndTakesTheSingleRunPath) {
  testing::TempDir dir("calibrate_flights_test");
  const BoardRun board = Chamber(ThermalProfileKind::kRamp, 21);
  const std::string log = testing::WriteFile(dir / "ramp.ulg", *EncodeBoardULog(board, board.fs_hz));
  Result<CalibrateResult> r = CalibrateLogs({log}, CalibrateOptions{});
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->logs.size(), 1u);
  EXPECT_TRUE(r->logs[0].detection.rejected.empty()) << r->logs[0].detection.BriefReport();
  EXPECT_EQ(r->logs[0].detection.segments.size(), 1u);
  for (const CalibratedSensor& s : r->sensors) {
    EXPECT_EQ(s.fit, "single run") << s.type;
    EXPECT_TRUE(s.calibrated()) << s.reason;
    EXPECT_FALSE(s.identification.statement.empty());
  }
}

// Two chamber runs of one board, a heating ramp and a cooling staircase, pooled against each run
// alone, scored as the firmware applies the file on held-out runs in both directions (a heating
// ramp and a cooling staircase of other seeds): the pooled file is never worse than the better
// single run's over both. Per direction it need not be: the simulated unit has a hysteresis, and
// a run calibrated in one direction fits that branch, so the ramp alone can win on the held-out
// ramp and the staircase alone on the held-out staircase; a firmware cubic has no memory, and
// the pooled curve is the one that holds for a next run of either direction. Measured, mrad/s
// (held-out ramp, staircase, both): seeds 31-34 pooled 0.141 0.323 0.249, ramp alone 0.125 0.360
// 0.270, staircase alone 0.181 0.339 0.272; seeds 41-44 pooled 0.155 0.322 0.253, ramp alone 0.169
// 0.386 0.298, staircase alone 0.184 0.353 0.281. One pair here (about 2 min under load).
TEST(CalibrateFlights, TwoChamberRunsPooledAreNeverWorseThanTheBetterSingleRun) {
  testing::TempDir dir("calibrate_flights_test");
  for (std::uint64_t seed : {31u}) {
    const BoardRun ramp = Chamber(ThermalProfileKind::kRamp, seed), steps = Chamber(ThermalProfileKind::kPaper, seed + 1);
    const std::vector<BoardRun> held_out = {Chamber(ThermalProfileKind::kRamp, seed + 3),
                                            Chamber(ThermalProfileKind::kPaper, seed + 2)};
    const std::string a = testing::WriteFile(dir / "ramp.ulg", *EncodeBoardULog(ramp, ramp.fs_hz));
    const std::string b = testing::WriteFile(dir / "steps.ulg", *EncodeBoardULog(steps, steps.fs_hz));
    // Per held-out run, the RMS over the three axes of its true drift against the exported cubic
    // (firmware clamp), boot offset removed.
    auto score = [&](const std::vector<std::string>& logs) {
      Result<CalibrateResult> r = CalibrateLogs(logs, CalibrateOptions{});
      EXPECT_TRUE(r.ok()) << r.error().message;
      const CalibratedSensor& g = r->sensors[0];
      EXPECT_EQ(g.type, "gyro");
      EXPECT_TRUE(g.calibrated()) << g.reason;
      std::vector<double> per_run;
      for (const BoardRun& h : held_out) {
        double ss = 0.0;
        for (int k = 0; k < 3; ++k) {
          std::vector<double> idx;
          for (std::size_t i = 0; i < h.time_s.size(); i += 10) idx.push_back(static_cast<double>(i));
          const double e = RmsAfterOffset(
              idx, [&](double i) { return h.imus[0].true_gyro_drift_rad_s[k][static_cast<std::size_t>(i)]; },
              [&](double i) { return g.cubics[k].Evaluate(h.imus[0].temp_c[static_cast<std::size_t>(i)]); });
          ss += e * e;
        }
        per_run.push_back(std::sqrt(ss / 3.0));
      }
      return per_run;
    };
    const std::vector<double> pooled = score({a, b}), only_a = score({a}), only_b = score({b});
    auto both = [](const std::vector<double>& v) { return std::hypot(v[0], v[1]) / std::sqrt(2.0); };
    std::printf("seed %llu held-out gyro RMS, mrad/s (heating ramp, cooling staircase, both): pooled %.4f %.4f %.4f; "
                "ramp alone %.4f %.4f %.4f; staircase alone %.4f %.4f %.4f\n",
                static_cast<unsigned long long>(seed), 1e3 * pooled[0], 1e3 * pooled[1], 1e3 * both(pooled),
                1e3 * only_a[0], 1e3 * only_a[1], 1e3 * both(only_a), 1e3 * only_b[0], 1e3 * only_b[1],
                1e3 * both(only_b));
    EXPECT_LE(both(pooled), std::min(both(only_a), both(only_b))) << "seed " << seed;
  }
}

// --optimise-for on a pooled fit, against its definition computed here from the rows the fit saw:
// two heating ramps of one board (1 and 3 C/min: the rates identify the dT/dt gain g), the
// heating state s(T) = per 1 C bin from the lowest temperature the median dT/dt (the slope over
// +-30 s of the row's log) of the rows heating at >= 1/300 C/s, 0 in bins without any; then the
// cubic is the least-squares cubic over 401 temperatures of the range of curve(T) + w g s(T), the
// curve the steady file's cubic, w = 1 (warm-up) or 1/2 (both). Tolerance 1e-6 of the largest
// warm-up effect |g s|: the fit and this check differ only by rounding (both are one linear
// solve; an off-by-one in the bins or the window moves it by >= 1e-3 of it). An axis without the
// term (g = 0) and every accelerometer axis here (no term kept) keep the steady cubic exactly.
TEST(CalibrateFlights, APooledFileOptimisedForWarmUpIsTheCurvePlusTheGainTimesTheHeatingState) {
  testing::TempDir dir("calibrate_flights_test");
  // The bench's board (bench/imu_calibration_side_by_side.py): 120 s lag, 10 -> 60 C.
  auto ramp = [](double rate_c_per_min, std::uint64_t seed) {
    BoardSimOptions o;
    o.chamber.profile.kind = ThermalProfileKind::kRamp;
    o.chamber.profile.room_temp_c = 10.0, o.chamber.profile.room_hold_s = 600.0, o.chamber.profile.hold_s = 600.0;
    o.chamber.profile.ramp_end_c = 60.0, o.chamber.profile.ramp_rate_c_per_min = rate_c_per_min;
    o.chamber.thermal_lag_s = 120.0, o.chamber.fs_hz = 10.0, o.chamber.seed = seed, o.num_imus = 1;
    Result<BoardRun> b = SimulateBoard(o);
    EXPECT_TRUE(b.ok()) << b.error().message;
    return *b;
  };
  const BoardRun slow = ramp(1.0, 51), fast = ramp(3.0, 52);
  const std::vector<std::string> logs = {testing::WriteFile(dir / "slow.ulg", *EncodeBoardULog(slow, slow.fs_hz)),
                                         testing::WriteFile(dir / "fast.ulg", *EncodeBoardULog(fast, fast.fs_hz))};
  auto run = [&](const char* condition) {
    CalibrateOptions opt;
    opt.optimise_for = condition;
    opt.pooled_lags_s.clear();  // the dT/dt term, not a lag, is what this test checks
    Result<CalibrateResult> r = CalibrateLogs(logs, opt);
    EXPECT_TRUE(r.ok()) << r.error().message;
    return *r;
  };
  const CalibrateResult steady = run("steady"), warm = run("warm-up"), both = run("both");
  const CalibratedSensor& g = steady.sensors[0];
  ASSERT_EQ(g.type, "gyro");
  ASSERT_EQ(g.fit, "pooled");
  ASSERT_TRUE(g.calibrated()) << g.reason;
  // The heating state from the fit rows: rate over +-30 s inside each log, median per 1 C bin.
  const CalibratedSensor::FitRows& rows = g.fit_rows;
  const std::size_t n = rows.temp_c.size();
  ASSERT_EQ(rows.time_s.size(), n);
  const double t0 = *std::min_element(rows.temp_c.begin(), rows.temp_c.end());
  std::vector<std::vector<double>> bins(static_cast<std::size_t>((*std::max_element(rows.temp_c.begin(), rows.temp_c.end()) - t0)) + 1);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t lo = i, hi = i;
    while (lo > 0 && rows.log[lo - 1] == rows.log[i] && rows.time_s[i] - rows.time_s[lo - 1] <= 30.0) --lo;
    while (hi + 1 < n && rows.log[hi + 1] == rows.log[i] && rows.time_s[hi + 1] - rows.time_s[i] <= 30.0) ++hi;
    const double rate = hi > lo ? (rows.temp_c[hi] - rows.temp_c[lo]) / (rows.time_s[hi] - rows.time_s[lo]) : 0.0;
    if (rate >= 1.0 / 300.0) bins[static_cast<std::size_t>(rows.temp_c[i] - t0)].push_back(rate);
  }
  std::vector<double> state;
  for (auto& b : bins) {
    std::sort(b.begin(), b.end());
    state.push_back(b.empty() ? 0.0 : b[b.size() / 2]);
  }
  auto state_at = [&](double t) {
    const auto i = static_cast<long>(std::floor((t - t0) / 1.0));
    return state[static_cast<std::size_t>(std::clamp<long>(i, 0, static_cast<long>(state.size()) - 1))];
  };
  ASSERT_EQ(warm.sensors[0].heating_state_kind, "dtemp_c_per_s");
  int with_term = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    const double gain = g.rate_gain[k];  // rad/s per C/s
    with_term += gain != 0.0;
    for (const auto& [result, w] : {std::pair{&warm, 1.0}, std::pair{&both, 0.5}}) {
      const TemperatureCubic& c = g.cubics[k];
      double largest = 0.0;  // the term's largest effect
      for (int i = 0; i <= 400; ++i) largest = std::max(largest, std::abs(gain * state_at(c.temp_min_c + (c.temp_max_c - c.temp_min_c) * i / 400.0)));
      const TemperatureCubic& got = result->sensors[0].cubics[k];
      const double weight = w;  // Clang 14 refuses to capture a structured binding in a lambda
      ExpectLeastSquaresCubic(c, [&](double t) { return c.Evaluate(t) + weight * gain * state_at(t); }, got,
                              1e-6 * std::max(largest, 1e-12), g.cols[k] + " w " + std::to_string(w));
      if (gain == 0.0) {
        EXPECT_EQ(got.coeff, c.coeff) << g.cols[k];
      }
    }
  }
  EXPECT_GE(with_term, 1) << "the 1 and 3 C/min ramps identify the dT/dt gain on at least one axis";
  // An accelerometer without the term: the same cubic whatever the condition.
  const CalibratedSensor& acc = steady.sensors[1];
  ASSERT_EQ(acc.type, "accel");
  if (acc.heating_state_kind.empty()) {
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(warm.sensors[1].cubics[k].coeff, acc.cubics[k].coeff);
    }
  }
}

}  // namespace
}  // namespace gyrocomp
