// Tests of the chamber simulator: the paper's temperature schedule, the thermal lag, the drift
// terms, determinism, and round trips through the Allan analysis (inject ARW / bias instability /
// RRW / quantization, recover each within a tolerance derived from the estimate's statistics).
#include "gyrocomp/sim/simulator.h"

#include <cmath>
#include <fstream>
#include <iterator>
#include <numeric>

#include <gtest/gtest.h>

#include "gyrocomp/allan/allan.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

// A quiet sensor: no drift, no noise, exact temperature. Tests switch on what they examine.
SimulatorOptions Quiet() {
  SimulatorOptions o;
  o.bias.poly_dps.clear();
  o.bias.dtemp_coeff_dps_per_c_per_s = 0.0;
  o.bias.hysteresis_coeff_dps_per_c = 0.0;
  o.noise.arw_deg_per_sqrt_h = 0.0;
  o.noise.bias_instability_deg_per_h = 0.0;
  o.noise.rrw_deg_per_h_per_sqrt_h = 0.0;
  o.temp_noise_c = 0.0;
  return o;
}

SimulatorOptions Soak(double hours, double fs_hz) {
  SimulatorOptions o = Quiet();
  o.profile.kind = ThermalProfileKind::kSoak;
  o.profile.soak_duration_s = hours * 3600.0;
  o.fs_hz = fs_hz;
  return o;
}

// Standard error of ln(adev) at point j: 1 / sqrt(2 EDF).
double LogSe(const AllanCurve& c, std::size_t j) { return 1.0 / std::sqrt(2.0 * c.edf[j]); }

// ---- temperature schedule and lag ----------------------------------------------------------

TEST(SimulatorSchedule, PaperProfileIsSection41) {
  Result<ThermalSchedule> s = MakeThermalSchedule(ThermalProfileOptions{});
  ASSERT_TRUE(s.ok());
  // 1 h at 25 C, 35 min ramp to 60 C (1 C/min), 1 h hold, then 10 x (10 min ramp + 1 h hold)
  // down to -40 C: 3600 + 2100 + 3600 + 10 * 4200 = 51300 s (14.25 h).
  EXPECT_DOUBLE_EQ(s->duration_s(), 51300.0);
  EXPECT_DOUBLE_EQ(s->ChamberTempC(1800.0), 25.0);
  EXPECT_DOUBLE_EQ(s->ChamberTempC(3600.0 + 1050.0), 42.5);  // half-way up the first ramp
  EXPECT_DOUBLE_EQ(s->ChamberTempC(5700.0 + 1800.0), 60.0);
  // The plateaus: 60, 50, ..., -40, each held 3600 s.
  for (int k = 0; k <= 10; ++k) {
    const double plateau_start = 5700.0 + k * 4200.0;
    const double expected = 60.0 - 10.0 * k;
    EXPECT_DOUBLE_EQ(s->ChamberTempC(plateau_start + 1.0), expected) << "plateau " << k;
    EXPECT_DOUBLE_EQ(s->ChamberTempC(plateau_start + 3599.0), expected) << "plateau " << k;
  }
  EXPECT_DOUBLE_EQ(s->ChamberTempC(1e9), -40.0);

  // The simulated sensor follows: at the end of each 1 h hold it is within
  // 10 C * exp(-3000 s / 600 s) = 0.07 C of the set point (lag 600 s, last 10 C step 10 min).
  SimulatorOptions o = Quiet();
  o.fs_hz = 1.0;
  Result<SimulatedRun> run = Simulate(o);
  ASSERT_TRUE(run.ok());
  ASSERT_EQ(run->num_samples(), 51300u);
  for (int k = 0; k <= 10; ++k) {
    const auto i = static_cast<std::size_t>(5700 + k * 4200 + 3599);
    EXPECT_NEAR(run->sensor_temp_c[i], 60.0 - 10.0 * k, 0.07) << "plateau " << k;
  }
  EXPECT_NEAR(run->summary.min_temp_c, -40.0, 0.07);
  EXPECT_NEAR(run->summary.max_temp_c, 60.0, 0.07);
}

TEST(SimulatorSchedule, SoakRampCycle) {
  ThermalProfileOptions p;
  p.kind = ThermalProfileKind::kSoak;
  p.soak_temp_c = -10.0;
  p.soak_duration_s = 500.0;
  auto s = MakeThermalSchedule(p);
  ASSERT_TRUE(s.ok());
  EXPECT_DOUBLE_EQ(s->duration_s(), 500.0);
  EXPECT_DOUBLE_EQ(s->ChamberTempC(250.0), -10.0);

  p.kind = ThermalProfileKind::kRamp;
  p.ramp_end_c = -35.0;
  p.ramp_rate_c_per_min = 2.0;
  s = MakeThermalSchedule(p);
  ASSERT_TRUE(s.ok());
  EXPECT_DOUBLE_EQ(s->duration_s(), 3600.0 + 60.0 * 60.0 / 2.0 + 3600.0);  // 60 C at 2 C/min
  EXPECT_DOUBLE_EQ(s->ChamberTempC(3600.0 + 900.0), -5.0);

  // Cycle: heating and cooling over the same range, num_cycles times, back to room.
  p.kind = ThermalProfileKind::kCycle;
  p.num_cycles = 2;
  p.ramp_rate_c_per_min = 1.0;
  s = MakeThermalSchedule(p);
  ASSERT_TRUE(s.ok());
  const double cycle_s = 35 * 60 + 3600 + 100 * 60 + 3600 + 65 * 60 + 3600;
  EXPECT_DOUBLE_EQ(s->duration_s(), 3600.0 + 2 * cycle_s);
  int heating = 0, cooling = 0;
  for (std::size_t j = 1; j < s->time_s.size(); ++j) {
    heating += s->temp_c[j] > s->temp_c[j - 1];
    cooling += s->temp_c[j] < s->temp_c[j - 1];
  }
  EXPECT_EQ(heating, 4);  // room->hot, cold->room, twice
  EXPECT_EQ(cooling, 2);  // hot->cold, twice
  EXPECT_DOUBLE_EQ(s->temp_c.back(), 25.0);
}

TEST(SimulatorSchedule, ThermalLagIsExactFirstOrder) {
  // Ramp 25 -> 60 C at 1 C/min from equilibrium: T(t) = u(t) - s tau (1 - exp(-t / tau)).
  SimulatorOptions o = Quiet();
  o.profile.kind = ThermalProfileKind::kRamp;
  o.profile.room_hold_s = 0.0;
  o.fs_hz = 10.0;
  o.thermal_lag_s = 600.0;
  auto run = Simulate(o);
  ASSERT_TRUE(run.ok());
  const double s = 1.0 / 60.0;
  for (double t : {10.0, 600.0, 1000.0, 2000.0}) {
    const auto i = static_cast<std::size_t>(t * o.fs_hz);
    const double expected = 25.0 + s * t - s * 600.0 * (1.0 - std::exp(-t / 600.0));
    // Exact discretization of a linear input: only rounding (1e-9 C over 2e4 steps).
    EXPECT_NEAR(run->sensor_temp_c[i], expected, 1e-9) << "t=" << t;
  }
  // No lag: the sensor is the chamber.
  o.thermal_lag_s = 0.0;
  run = Simulate(o);
  ASSERT_TRUE(run.ok());
  EXPECT_EQ(run->sensor_temp_c, run->chamber_temp_c);
}

// ---- drift terms -------------------------------------------------------------------------------

TEST(SimulatorDrift, PolynomialAtConstantTemperature) {
  SimulatorOptions o = Soak(0.1, 10.0);
  o.profile.soak_temp_c = 40.0;
  o.bias.poly_dps = {0.01, 2e-3, -1e-5};
  auto run = Simulate(o);
  ASSERT_TRUE(run.ok());
  const double expected = 0.01 + 2e-3 * 15.0 - 1e-5 * 225.0;
  for (std::size_t i = 0; i < run->num_samples(); i += 97) {
    EXPECT_NEAR(run->true_drift_dps[i], expected, 1e-15);
    EXPECT_NEAR(run->rate_dps[i], expected, 1e-15);  // quiet sensor: output = drift
  }
}

TEST(SimulatorDrift, TemperatureRateTerm) {
  // Drift = k dT/dt only; dT/dt of the lagged sensor = (u - T) / lag, checked against a numerical
  // derivative of the sensor temperature (central difference: O(dt^2) ~ 1e-9 relative here).
  SimulatorOptions o = Quiet();
  o.profile.kind = ThermalProfileKind::kRamp;
  o.fs_hz = 10.0;
  o.bias.dtemp_coeff_dps_per_c_per_s = 2.0;
  auto run = Simulate(o);
  ASSERT_TRUE(run.ok());
  for (double t : {3700.0, 4500.0, 6000.0}) {
    const auto i = static_cast<std::size_t>(t * o.fs_hz);
    const double dTdt = (run->sensor_temp_c[i + 1] - run->sensor_temp_c[i - 1]) * o.fs_hz / 2.0;
    EXPECT_NEAR(run->true_drift_dps[i], 2.0 * dTdt, 1e-6 * std::abs(2.0 * dTdt)) << "t=" << t;
  }
  EXPECT_GT(run->true_drift_dps[static_cast<std::size_t>(4500 * o.fs_hz)], 0.02);  // heating: > 0
}

TEST(SimulatorDrift, HysteresisHeatingVersusCooling) {
  // Hysteresis only: +coeff*width/2 while heating, -coeff*width/2 while cooling (play operator).
  SimulatorOptions o = Quiet();
  o.profile.kind = ThermalProfileKind::kCycle;
  o.fs_hz = 1.0;
  o.bias.hysteresis_coeff_dps_per_c = 1e-3;
  o.bias.hysteresis_width_c = 4.0;
  auto run = Simulate(o);
  ASSERT_TRUE(run.ok());
  // Mid heating ramp (25 -> 60 starts at 3600 s) and mid cooling ramp (60 -> -40 starts at 9300 s).
  EXPECT_NEAR(run->true_drift_dps[3600 + 1500], +2e-3, 1e-12);
  EXPECT_NEAR(run->true_drift_dps[9300 + 3000], -2e-3, 1e-12);
  // At the same sensor temperature, heating and cooling differ by coeff * width.
  const std::size_t up = 3600 + 1500;
  std::size_t down = 9300;
  while (run->sensor_temp_c[down] > run->sensor_temp_c[up]) ++down;
  EXPECT_NEAR(run->true_drift_dps[up] - run->true_drift_dps[down], 4e-3, 1e-12);
}

TEST(SimulatorTruth, TrueRateStepsSineConstant) {
  SimulatorOptions o = Soak(0.5, 10.0);
  o.true_rate.constant_dps = 0.004;
  o.true_rate.step_amplitude_dps = 1.0;
  o.true_rate.step_period_s = 100.0;
  o.true_rate.sine_amplitude_dps = 0.5;
  o.true_rate.sine_frequency_hz = 0.01;
  auto run = Simulate(o);
  ASSERT_TRUE(run.ok());
  auto expected = [](double t) {
    const int phase = static_cast<int>(std::floor(t / 100.0)) % 4;
    return 0.004 + (phase == 1 ? 1.0 : phase == 3 ? -1.0 : 0.0) + 0.5 * std::sin(2 * M_PI * 0.01 * t);
  };
  for (double t : {5.0, 150.0, 250.0, 333.3, 1234.5}) {
    const auto i = static_cast<std::size_t>(std::llround(t * o.fs_hz));
    EXPECT_NEAR(run->true_rate_dps[i], expected(run->time_s[i]), 1e-12) << "t=" << t;
    EXPECT_NEAR(run->rate_dps[i], run->true_rate_dps[i], 1e-12);  // quiet sensor
  }
}

// ---- determinism and output ---------------------------------------------------------------------

TEST(SimulatorDeterminism, SameSeedSameRunOtherSeedOtherRun) {
  SimulatorOptions o;  // defaults: every term on
  o.duration_s = 600.0;
  auto a = Simulate(o), b = Simulate(o);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->rate_dps, b->rate_dps);
  EXPECT_EQ(a->temp_c, b->temp_c);
  o.seed = 2;
  auto c = Simulate(o);
  ASSERT_TRUE(c.ok());
  EXPECT_NE(a->rate_dps, c->rate_dps);
  EXPECT_EQ(a->true_drift_dps, c->true_drift_dps);  // the drift is deterministic
  // The normal generator is our own (portable): fixed values for seed 1, so an accidental change
  // of the algorithm shows. Tolerance 1e-12: only libm's log/sqrt may differ in the last ulp.
  NormalGenerator g(1);
  const double first[3] = {g.Next(), g.Next(), g.Next()};
  NormalGenerator h(1);
  for (double v : first) EXPECT_EQ(h.Next(), v);
  // Moments of 1e6 draws: mean within 5 / sqrt(n), variance within 5 sqrt(2 / n).
  double sum = 0, sum2 = 0;
  const int n = 1000000;
  for (int i = 0; i < n; ++i) {
    const double v = g.Next();
    sum += v;
    sum2 += v * v;
  }
  EXPECT_NEAR(sum / n, 0.0, 5.0 / std::sqrt(n));
  EXPECT_NEAR(sum2 / n, 1.0, 5.0 * std::sqrt(2.0 / n));
}

TEST(SimulatorOutput, TableColumnsAndErrors) {
  SimulatorOptions o;
  o.duration_s = 10.0;
  auto run = Simulate(o);
  ASSERT_TRUE(run.ok());
  EXPECT_EQ(run->num_samples(), 1000u);
  EXPECT_DOUBLE_EQ(run->time_s[999], 9.99);
  const Table t = run->ToTable();
  EXPECT_EQ(t.names, (std::vector<std::string>{"time_s", "rate_dps", "temp_c", "chamber_temp_c", "sensor_temp_c",
                                               "true_rate_dps", "true_drift_dps", "true_noise_dps"}));
  ASSERT_EQ(t.columns.size(), t.names.size());
  for (const auto& col : t.columns) EXPECT_EQ(col.size(), 1000u);
  // rate = truth + drift + noise, by construction of the truth columns.
  for (std::size_t i = 0; i < 1000; ++i) {
    EXPECT_NEAR(run->rate_dps[i], run->true_rate_dps[i] + run->true_drift_dps[i] + run->true_noise_dps[i], 1e-15);
  }
  const Table moved = std::move(*run).ToTable();  // the moving overload gives the same table
  EXPECT_EQ(moved.names, t.names);
  EXPECT_EQ(moved.columns, t.columns);

  o.profile.step_c = 0.0;
  auto bad = Simulate(o);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().kind, ErrorKind::kInvalidArgument);
  EXPECT_EQ(bad.error().message, "ThermalProfileOptions::step_c = 0: must be > 0");
  o = SimulatorOptions{};
  o.noise.arw_deg_per_sqrt_h = -1.0;
  EXPECT_EQ(Simulate(o).error().message, "NoiseOptions::arw_deg_per_sqrt_h = -1: must be >= 0 (0 = off)");
  o = SimulatorOptions{};
  o.fs_hz = 0.0;
  EXPECT_EQ(Simulate(o).error().kind, ErrorKind::kInvalidArgument);
  o = SimulatorOptions{};
  o.duration_s = 0.001;
  EXPECT_EQ(Simulate(o).error().kind, ErrorKind::kInvalidArgument);
}

// ---- round trips through the Allan analysis ---------------------------------------------------

TEST(SimulatorRoundTrip, AngleRandomWalk) {
  SimulatorOptions o = Soak(2.0, 100.0);
  o.noise.arw_deg_per_sqrt_h = 1.0;
  auto run = Simulate(o);
  ASSERT_TRUE(run.ok());
  auto a = ComputeAllan(run->rate_dps, o.fs_hz);
  ASSERT_TRUE(a.ok());
  // sigma(1 s) with 7.2e5 samples: EDF ~ 3N/2m = 1.1e4 at m = 100, 0.7% standard error -> 3%.
  EXPECT_NEAR(*a->terms.arw_deg_per_sqrt_h, 1.0, 0.03);
  EXPECT_NEAR(*a->terms.arw_fit_deg_per_sqrt_h, 1.0, 0.03);
}

TEST(SimulatorRoundTrip, BiasInstabilityFlickerFloor) {
  // The model's own floor: ModelAdevDps = 0.664 B at the band's geometric middle (by construction)
  // and within 2% of it across [200 s, 1.6e4 s] = [20 T_min, T_max / 6] (sum of Gauss-Markov
  // processes, 2 per decade, correlation times 10 s .. 1e5 s).
  NoiseOptions n;
  n.arw_deg_per_sqrt_h = 0.0;
  n.rrw_deg_per_h_per_sqrt_h = 0.0;
  n.bias_instability_deg_per_h = 30.0;
  const double floor_dph = 0.664 * 30.0;
  EXPECT_NEAR(ModelAdevDps(n, std::sqrt(10.0 * 1e5)) * 3600.0, floor_dph, 1e-9);
  for (double tau = 200.0; tau <= 1.6e4; tau *= 1.5) {
    EXPECT_NEAR(ModelAdevDps(n, tau) * 3600.0, floor_dph, 0.02 * floor_dph) << "tau=" << tau;
  }
  // Simulated: 40 h at 2 Hz with white noise (ARW 1 deg/sqrt(h): it meets the floor near 9 s,
  // where the flicker is still rising, so the curve has no dip below the floor; with much less
  // white noise the minimum falls below 0.664 B at ~10 s, see docs/explanation/simulator.md). Over tau in
  // [64, 2048] s the ADEV must
  // follow the model: the EDF-weighted mean of ln(adev / model) is within 3x its standard error
  // bound (mean of 1/sqrt(2 EDF), fully-correlated case).
  SimulatorOptions o = Soak(40.0, 2.0);
  o.noise = n;
  o.noise.arw_deg_per_sqrt_h = 1.0;
  auto run = Simulate(o);
  ASSERT_TRUE(run.ok());
  auto a = ComputeAllan(run->rate_dps, o.fs_hz);
  ASSERT_TRUE(a.ok());
  double sum = 0, wsum = 0, se = 0;
  int count = 0;
  for (std::size_t j = 0; j < a->curve.size(); ++j) {
    const double tau = a->curve.tau_s[j];
    if (tau < 64.0 || tau > 2048.0) continue;
    const double w = 2.0 * a->curve.edf[j];
    sum += w * std::log(a->curve.adev_dps[j] / ModelAdevDps(o.noise, tau));
    wsum += w;
    se += LogSe(a->curve, j);
    ++count;
  }
  ASSERT_GE(count, 5);
  EXPECT_NEAR(sum / wsum, 0.0, 3.0 * se / count) << "bound " << se / count;
  // And the reported bias instability lands near the injected B. Two conventions:
  // - the default, the minimum of the whole curve (as allantools users and the paper read it),
  //   falls on this flicker-only record at one of the last taus in 8 of seeds 1-12 (16384 s ..
  //   65536 s, EDF 1 .. 6), at 0.19 .. 0.98 of the floor: a random dip of a point with one or
  //   two degrees of freedom, not a property of the simulator. Its tolerance would be
  //   3 / sqrt(2 EDF) ~ 2 in ln at EDF 1, a check that cannot fail, so it is not checked here;
  // - the EDF-qualified minimum (EDF >= 10) is: it is biased low by up to a few standard errors
  //   of the point where it falls (observed over seeds 1-12: -10% .. +2% of 0.664 B, at 256 s ..
  //   8192 s): tolerance 3 / sqrt(2 EDF) at that point, plus the 2% ripple of the flicker model.
  const AllanNoiseTerms& t = a->terms;
  std::size_t jmin = 0;
  while (a->curve.tau_s[jmin] != t.tau_at_min_usable_s) ++jmin;
  ASSERT_GE(a->curve.edf[jmin], t.min_edf);
  const double tol = 3.0 * LogSe(a->curve, jmin) + 0.02;
  EXPECT_NEAR(std::log(t.adev_min_usable_deg_per_h / 0.664 / 30.0), 0.0, tol) << a->BriefReport();
  // The whole-curve figure is the minimum over a superset of taus, and its flag says where it is.
  EXPECT_LE(t.adev_min_deg_per_h, t.adev_min_usable_deg_per_h);
  EXPECT_EQ(t.min_at_longest_tau, t.tau_at_min_s == a->curve.tau_s.back());
}

TEST(SimulatorRoundTrip, RateRandomWalk) {
  SimulatorOptions o = Soak(40.0, 2.0);
  o.noise.arw_deg_per_sqrt_h = 0.1;
  o.noise.rrw_deg_per_h_per_sqrt_h = 20.0;
  auto run = Simulate(o);
  ASSERT_TRUE(run.ok());
  auto a = ComputeAllan(run->rate_dps, o.fs_hz);
  ASSERT_TRUE(a.ok());
  ASSERT_TRUE(a->terms.rrw_deg_per_h_per_sqrt_h.has_value()) << a->BriefReport();
  double se = 0;
  int count = 0;
  for (std::size_t j = 0; j < a->curve.size(); ++j) {
    if (a->curve.tau_s[j] < *a->terms.rrw_fit_tau_min_s || a->curve.tau_s[j] > *a->terms.rrw_fit_tau_max_s) continue;
    if (std::abs(a->curve.slope[j] - 0.5) > AllanOptions{}.slope_tolerance) continue;
    se += LogSe(a->curve, j);
    ++count;
  }
  ASSERT_GT(count, 2);
  EXPECT_NEAR(std::log(*a->terms.rrw_deg_per_h_per_sqrt_h / 20.0), 0.0, 3.0 * se / count)
      << a->BriefReport();
}

TEST(SimulatorRoundTrip, AngleQuantization) {
  // Q = 0.01 deg with enough white noise to dither the angle over many steps: the ADEV follows
  // sqrt(N^2 / tau + 3 Q^2 / tau^2) (ModelAdevDps). 1e5 samples: EDF >= 3e4 for m <= 4, i.e.
  // < 0.5% standard error per point; 2% allows for the rounding error not being exactly uniform.
  SimulatorOptions o = Soak(1000.0 / 3600.0, 100.0);
  o.noise.arw_deg_per_sqrt_h = 10.0;
  o.noise.quantization_deg = 0.01;
  auto run = Simulate(o);
  ASSERT_TRUE(run.ok());
  auto a = ComputeAllan(run->rate_dps, o.fs_hz);
  ASSERT_TRUE(a.ok());
  for (std::size_t j = 0; j < 3; ++j) {
    const double model = ModelAdevDps(o.noise, a->curve.tau_s[j]);
    EXPECT_NEAR(a->curve.adev_dps[j], model, 0.02 * model) << "tau=" << a->curve.tau_s[j];
  }
  // Without quantization the same seed gives the white-noise-only level, clearly lower at 10 ms.
  o.noise.quantization_deg = 0.0;
  auto b = ComputeAllan(Simulate(o)->rate_dps, o.fs_hz);
  EXPECT_LT(b->curve.adev_dps[0], 0.8 * a->curve.adev_dps[0]);
}

TEST(SimulatorRoundTrip, DefaultsReproduceThePapersRawFigures) {
  // The paper's raw record: ARW 1.667 deg/sqrt(h), bias stability (ADEV minimum) 30 deg/h. The
  // default run at 20 Hz (the noise terms are specified per second, so the figures do not depend
  // on fs; 20 Hz keeps the test fast): ARW within 3% (0.7% standard error + ~0.5% flicker
  // leakage at 1 s), ADEV minimum within 10% (observed 29.1 .. 30.6 deg/h over seeds 1-6 at
  // 100 Hz; one point's standard error near tau = 100 s is ~3%). Re-derived for the whole-curve
  // minimum: the drift makes the curve rise after ~200 s, so the minimum of the whole
  // curve is the EDF-qualified one on this run: 29.35 .. 30.26 deg/h at 51 .. 205 s over seeds
  // 1-6 at 20 Hz (`gyrocomp simulate --fs 20 --seed S`, then `gyrocomp allan --json -`).
  SimulatorOptions o;
  o.fs_hz = 20.0;
  auto run = Simulate(o);
  ASSERT_TRUE(run.ok());
  EXPECT_NEAR(run->summary.duration_s, 51300.0, 1e-6);
  auto a = ComputeAllan(run->rate_dps, o.fs_hz);
  ASSERT_TRUE(a.ok());
  EXPECT_NEAR(*a->terms.arw_deg_per_sqrt_h, 1.667, 0.03 * 1.667) << a->BriefReport();
  EXPECT_NEAR(a->terms.adev_min_deg_per_h, 30.0, 3.0) << a->BriefReport();
  EXPECT_FALSE(a->terms.min_at_longest_tau);
  EXPECT_EQ(a->terms.tau_at_min_s, a->terms.tau_at_min_usable_s) << a->BriefReport();
}

// ---- the CLI, end to end ----------------------------------------------------------------------

TEST(SimulatorCli, DeterministicCsvWithTruthColumns) {
  const std::string cli = testing::CliPath();
  if (cli.empty() || !std::ifstream(cli).good()) GTEST_SKIP() << "the gyrocomp CLI is not built";
  const std::string dir = testing::MakeTempDir("simulate_cli");
  std::string out;
  const std::string args = " simulate --profile cycle --fs 5 --duration 600 --seed 9 --sine-amplitude 0.2";
  ASSERT_EQ(testing::RunCommand(cli + args + " -o " + dir + "/a.csv --json " + dir + "/a.json", &out), 0) << out;
  ASSERT_EQ(testing::RunCommand(cli + args + " -o " + dir + "/b.csv", &out), 0) << out;
  auto read = [](const std::string& p) {
    std::ifstream f(p);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  EXPECT_EQ(read(dir + "/a.csv"), read(dir + "/b.csv"));  // same seed: byte-identical
  const auto csv = testing::ReadGoldenCsv(dir + "/a.csv");
  for (const char* col : {"time_s", "rate_dps", "temp_c", "true_rate_dps", "true_drift_dps", "true_noise_dps"}) {
    ASSERT_TRUE(csv.count(col)) << col;
    EXPECT_EQ(csv.at(col).size(), 3000u) << col;
  }
  EXPECT_NEAR(csv.at("true_rate_dps")[25], 0.2 * std::sin(2 * M_PI * 0.01 * 5.0), 1e-12);
  EXPECT_EQ(testing::ReadJsonFile(dir + "/a.json")["n_samples"].get<int>(), 3000);
  // The library's own check of the options: exit 2, the field named, no file.
  EXPECT_EQ(testing::RunCommand(cli + " simulate --step 0 -o " + dir + "/c.csv", &out), 2) << out;
  EXPECT_NE(out.find("ThermalProfileOptions::step_c = 0"), std::string::npos) << out;
  EXPECT_FALSE(std::ifstream(dir + "/c.csv").good());
}

}  // namespace
}  // namespace gyrocomp
