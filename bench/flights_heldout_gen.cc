// Writes one board's logs for bench/calibrate_flights_heldout.py: ten ordinary flight logs, a
// dedicated chamber calibration run and three held-out chamber runs (heating, cooling, warm-up),
// all PX4 ULogs of a 3-IMU board, with the ground truth in truth.json.
//
// Two generators of different structure:
//   1  gyrocomp's own flight simulator (SimulateFlight, gyrocomp/sim/flight.h: the board
//      temperature drives a cubic drift); the chamber runs are built here (first-order chamber
//      lag and self-heating, the same cubic through FlightGyroDriftRadS / FlightAccelDriftM_S2).
//   2  written here, apart from src/sim/flight.cc: a two-node board (board and die, airflow
//      cooling in flight) whose logged temperature is the die thermometer, the MEMS structure
//      lagging it by a second-order lag (two cascaded first-order lags); per-axis curves that are
//      not cubics (tanh, exponential, a smoothed kink, with a sinusoidal ripple); a Gauss-Markov
//      bias wander; attitude from smooth Euler-angle processes; motor vibration as aliased tones
//      plus AR(1) noise; disarmed handling (carried to the take-off spot, a touch while it warms,
//      picked up after landing) that the log's armed / landed state does not show; and the IMU
//      instance order (ULog multi_id) shuffled at every power-on, the device ids staying with
//      the chips (EncodeFlightULog's order).
// Every power-on has its own offset: 0.05 deg/s per gyro axis, 20 mg per accelerometer axis
// (1 sigma). Not part of the CMake build; the script compiles it against build/libgyrocomp.a.
//
// truth.json: per flight, the truly still intervals (log time, s); per sensor (type, IMU, device
// id) the temperature range of the flights' still rows and, on each held-out run, the score of no
// correction and of the least-squares cubic of the true static curve over that range, both as
// `calibrate --validation` scores (PX4 formula in float, T clamped; RMS of 10 s block means,
// their mean removed; the rows read back from the written ULog as 1 s means).
//
// Usage: flights_heldout_gen OUT_DIR GENERATOR(1|2) BOARD SEED [RATE_HZ=50] [LAG_SCALE=1]
// (LAG_SCALE multiplies generator 2's MEMS lag behind the die thermometer; 0: none.)
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "gyrocomp/export/cubic_score.h"
#include "gyrocomp/export/thermal_cubic.h"
#include "gyrocomp/io/ulog.h"
#include "gyrocomp/sim/flight.h"
#include "gyrocomp/sim/simulator.h"

namespace {

using gyrocomp::FlightRun;
constexpr double kG = 9.80665;
constexpr double kRadPerDeg = std::numbers::pi / 180.0;
constexpr int kImus = 3;
constexpr int kFlights = 10;

using Curve = std::function<double(double)>;  // static drift at temperature T, firmware unit

// A board's truth: per IMU and axis the static curve (gyro rad/s, accel m/s^2).
struct Truth {
  std::array<std::array<Curve, 3>, kImus> gyro, accel;
};

struct Rng {
  std::mt19937_64 e;
  explicit Rng(std::uint64_t seed) : e(seed) {}
  double N() { return std::normal_distribution<double>(0.0, 1.0)(e); }
  double U(double a, double b) { return std::uniform_real_distribution<double>(a, b)(e); }
  double Sign() { return U(0.0, 1.0) < 0.5 ? -1.0 : 1.0; }
};

// ---- chamber profiles (both generators) -----------------------------------------------------
// Chamber air temperature over time and the run's length.
struct ChamberProfile {
  std::string name;
  double start_c, hold_s, ramp_c_per_min, end_c, end_hold_s;
  double Duration() const { return hold_s + std::abs(end_c - start_c) / ramp_c_per_min * 60.0 + end_hold_s; }
  double At(double t) const {
    if (t < hold_s) return start_c;
    const double ramp_s = std::abs(end_c - start_c) / ramp_c_per_min * 60.0;
    if (t < hold_s + ramp_s) return start_c + (end_c - start_c) * (t - hold_s) / ramp_s;
    return end_c;
  }
};
// PX4's procedure: cold soak, power on, let the board warm with the chamber heating slowly.
const ChamberProfile kCalibration{"calibration", -5.0, 600.0, 1.0, 55.0, 600.0};
// Held out: heating, cooling and a warm-up over the flights' ambients (0..35 C), and a heating
// to 55 C that goes beyond the temperatures the flights reach.
const std::vector<ChamberProfile> kHeldOut = {{"heating", 0.0, 1200.0, 0.5, 35.0, 300.0},
                                              {"cooling", 35.0, 1200.0, 0.5, 0.0, 300.0},
                                              {"warm-up", 15.0, 2400.0, 1.0, 15.0, 0.0},
                                              {"wide-heating", 5.0, 1200.0, 0.8, 55.0, 300.0}};

FlightRun EmptyRun(std::size_t n, double fs) {
  FlightRun r;
  r.time_s.resize(n), r.temp_c.resize(n);
  for (auto& v : r.gyro_rad_s) v.resize(n);
  for (auto& v : r.accel_m_s2) v.resize(n);
  r.armed.assign(n, false), r.landed.assign(n, true), r.truly_still.assign(n, true);
  for (std::size_t i = 0; i < n; ++i) r.time_s[i] = static_cast<double>(i) / fs;
  return r;
}

// Gravity's specific force in the sensor frame (FRD) at roll / pitch (rad): R^T (0, 0, -g).
std::array<double, 3> GravityFrd(double roll, double pitch) {
  return {kG * std::sin(pitch), -kG * std::sin(roll) * std::cos(pitch), -kG * std::cos(roll) * std::cos(pitch)};
}

// ---- generator 1 ------------------------------------------------------------------------------
struct Gen1Board {
  std::array<gyrocomp::FlightSimOptions, kImus> imu;  // drift, scales; the flight fields per flight
};

Gen1Board MakeGen1Board(int board) {
  Rng r(7919ULL * static_cast<std::uint64_t>(board) + 11);
  Gen1Board b;
  const double heat = r.U(10.0, 18.0), tau = r.U(300.0, 600.0), air = r.U(5.0, 10.0);
  for (int k = 0; k < kImus; ++k) {
    gyrocomp::FlightSimOptions& o = b.imu[static_cast<std::size_t>(k)];
    o.fs_hz = 50.0;
    o.self_heating_c = heat, o.self_heating_tau_s = tau, o.airflow_cooling_c = air;
    o.gyro_drift_dps = {0.0, r.Sign() * r.U(2e-3, 8e-3), r.Sign() * r.U(0.0, 3e-4), r.Sign() * r.U(0.0, 6e-6)};
    o.accel_drift_m_s2 = {0.0, r.Sign() * r.U(1e-3, 5e-3), r.Sign() * r.U(0.0, 2e-4), r.Sign() * r.U(0.0, 4e-6)};
    o.axis_scale = {r.Sign() * r.U(0.5, 1.0), r.Sign() * r.U(0.5, 1.0), r.Sign() * r.U(0.5, 1.0)};
  }
  return b;
}

Truth Gen1Truth(const Gen1Board& b) {
  Truth t;
  for (int k = 0; k < kImus; ++k)
    for (int a = 0; a < 3; ++a) {
      const gyrocomp::FlightSimOptions o = b.imu[static_cast<std::size_t>(k)];
      t.gyro[k][a] = [o, a](double T) { return gyrocomp::FlightGyroDriftRadS(o, a, T); };
      t.accel[k][a] = [o, a](double T) { return gyrocomp::FlightAccelDriftM_S2(o, a, T); };
    }
  return t;
}

// A chamber run of a generator-1 board: board temperature = first-order lag (300 s) of the
// chamber plus the self-heating (first order from power-on), the cubic of it, offsets, white noise.
std::vector<FlightRun> Gen1Chamber(const Gen1Board& b, const Truth& truth, const ChamberProfile& p, double fs, Rng& r) {
  const auto n = static_cast<std::size_t>(p.Duration() * fs);
  std::vector<FlightRun> out;
  const double roll = r.N() * 2.0 * kRadPerDeg, pitch = r.N() * 2.0 * kRadPerDeg;
  for (int k = 0; k < kImus; ++k) {
    const gyrocomp::FlightSimOptions& o = b.imu[static_cast<std::size_t>(k)];
    FlightRun run = EmptyRun(n, fs);
    std::array<double, 3> g_off, a_off;
    for (int a = 0; a < 3; ++a) g_off[a] = r.N() * o.gyro_offset_dps * kRadPerDeg, a_off[a] = r.N() * o.accel_offset_m_s2;
    const std::array<double, 3> grav = GravityFrd(roll, pitch);
    double board = p.At(0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = run.time_s[i];
      board += (p.At(t) - board) / (300.0 * fs);
      const double T = board + o.self_heating_c * (1.0 - std::exp(-t / o.self_heating_tau_s));
      run.temp_c[i] = T;
      for (int a = 0; a < 3; ++a) {
        run.gyro_rad_s[a][i] = truth.gyro[k][a](T) + g_off[a] + r.N() * o.gyro_noise_dps * kRadPerDeg;
        run.accel_m_s2[a][i] = grav[a] + truth.accel[k][a](T) + a_off[a] + r.N() * o.accel_noise_m_s2;
      }
    }
    out.push_back(std::move(run));
  }
  return out;
}

// ---- generator 2 ------------------------------------------------------------------------------
// One IMU of a generator-2 board.
struct Gen2Imu {
  double heat_share = 1.0;  // its die's share of the board's self-heating
  double die_tau_s = 40.0;  // die node time constant, s
  double lag1_s = 15.0, lag2_s = 45.0;  // MEMS structure behind the die thermometer, s
  double gyro_noise_dps = 0.04, accel_noise_m_s2 = 0.03;  // white, per sample
  double gyro_wander_dps = 0.002, accel_wander_m_s2 = 0.002, wander_tau_s = 300.0;  // Gauss-Markov
};
struct Gen2Board {
  std::array<Gen2Imu, kImus> imu;
  double board_heat_c = 12.0, board_tau_s = 600.0;  // board node: rise over ambient, time constant
  double die_heat_c = 4.0;  // die node's own rise over the board
  double airflow = 0.8;  // in flight the heating's equilibrium divided by (1 + airflow * speed)
};

// A static curve that is not a cubic: tanh, exponential or a smoothed kink, with a ripple.
Curve MakeCurve(Rng& r, double scale) {
  const int family = static_cast<int>(r.U(0.0, 3.0));
  const double ripple = r.U(0.002, 0.008) * scale, period = r.U(25.0, 50.0), phase = r.U(0.0, 6.283);
  Curve base;
  if (family == 0) {
    const double A = r.Sign() * r.U(0.1, 0.3) * scale, T0 = r.U(10.0, 40.0), W = r.U(10.0, 25.0);
    base = [=](double T) { return A * std::tanh((T - T0) / W); };
  } else if (family == 1) {
    const double A = r.Sign() * r.U(0.02, 0.06) * scale, W = r.U(18.0, 30.0);
    base = [=](double T) { return A * (std::exp((T - 25.0) / W) - 1.0); };
  } else {
    const double s1 = r.Sign() * r.U(2e-3, 8e-3) * scale, s2 = r.Sign() * r.U(2e-3, 8e-3) * scale, Tk = r.U(15.0, 35.0), W = 2.0;
    base = [=](double T) {
      const double x = (T - Tk) / W;
      const double softplus = x > 30.0 ? x : std::log1p(std::exp(x));
      return s1 * (T - Tk) + (s2 - s1) * W * softplus;
    };
  }
  return [=](double T) { return base(T) + ripple * std::sin(2.0 * std::numbers::pi * T / period + phase); };
}

Gen2Board MakeGen2Board(int board, Truth* truth, double lag_scale) {
  Rng r(104729ULL * static_cast<std::uint64_t>(board) + 17);
  Gen2Board b;
  b.board_heat_c = r.U(8.0, 14.0), b.board_tau_s = r.U(400.0, 900.0), b.die_heat_c = r.U(2.0, 5.0);
  b.airflow = r.U(0.6, 1.2);
  for (int k = 0; k < kImus; ++k) {
    Gen2Imu& m = b.imu[static_cast<std::size_t>(k)];
    m.heat_share = r.U(0.8, 1.2), m.die_tau_s = r.U(20.0, 60.0);
    m.lag1_s = r.U(8.0, 25.0) * lag_scale + 1e-6, m.lag2_s = r.U(25.0, 70.0) * lag_scale + 1e-6;
    m.gyro_noise_dps = r.U(0.03, 0.06), m.accel_noise_m_s2 = r.U(0.02, 0.04);
    for (int a = 0; a < 3; ++a) {
      truth->gyro[k][a] = [c = MakeCurve(r, kRadPerDeg)](double T) { return c(T); };  // deg/s-sized, rad/s
      truth->accel[k][a] = [c = MakeCurve(r, 1.5)](double T) { return c(T); };     // m/s^2
    }
  }
  return b;
}

// What happens to the vehicle at each row: the phases' effect on motion, state and airflow.
struct Motion {
  std::vector<double> roll, pitch, yaw;  // rad
  std::vector<std::array<double, 3>> lin_acc_ned;  // m/s^2, besides gravity
  std::vector<double> vibration;  // 0 off, else motor on (scale of the per-flight amplitude)
  std::vector<double> speed;  // airflow, 0..1
  std::vector<bool> armed, landed, still;
};

// An Ornstein-Uhlenbeck step: x relaxes to 0 with tau, driven to stationary sd sigma.
double Ou(double x, double tau, double sigma, double dt, Rng& r) {
  const double a = std::exp(-dt / tau);
  return a * x + sigma * std::sqrt(1.0 - a * a) * r.N();
}

// The flight's timeline: power-on still (a touch in it, sometimes), carried to the take-off spot,
// still again, armed on the ground, flight, landed armed, still, sometimes picked up at the end.
// `quick`: a short hop (at most a minute still at each end, five minutes in the air). `warm`: a
// restart of a warm board (4..6 min still, two minutes in the air, 2..3 min still).
Motion Gen2Timeline(double fs, Rng& r, bool quick, bool warm = false) {
  Motion m;
  const double dt = 1.0 / fs;
  struct Phase { const char* kind; double s; };
  std::vector<Phase> ph = {{"still", quick ? r.U(30.0, 60.0) : r.U(60.0, 600.0)}, {"carry", r.U(15.0, 60.0)},
                           {"still", quick ? r.U(10.0, 25.0) : r.U(20.0, 120.0)}, {"armed", r.U(3.0, 10.0)},
                           {"fly", quick ? 300.0 : r.U(300.0, 1200.0)}, {"landed", r.U(2.0, 6.0)},
                           {"still", quick ? r.U(20.0, 40.0) : r.U(120.0, 600.0)}};
  if (warm) ph[0].s = r.U(240.0, 360.0), ph[4].s = 120.0, ph[6].s = r.U(120.0, 180.0);
  if (r.U(0.0, 1.0) < 0.5) ph.push_back({"carry", r.U(10.0, 30.0)});
  const bool touch = r.U(0.0, 1.0) < 0.6 && ph[0].s > 150.0;
  const double touch_at = touch ? r.U(50.0, ph[0].s - 60.0) : -1.0, touch_s = r.U(1.0, 3.0);
  double roll = r.N() * 2.0 * kRadPerDeg, pitch = r.N() * 2.0 * kRadPerDeg, yaw = r.U(-3.0, 3.0);
  double o_r = 0, o_p = 0, o_y = 0;  // OU states of the attitude in motion, rad
  std::array<double, 3> acc{};
  const double man_sd = r.U(10.0, 30.0) * kRadPerDeg, man_tau = r.U(0.7, 2.5);
  bool touched = false;
  for (std::size_t p = 0; p < ph.size(); ++p) {
    const auto n = static_cast<std::size_t>(ph[p].s * fs);
    const std::string kind = ph[p].kind;
    // Set-down attitude after a carry: a new tilt reached over the carry's last 2 s.
    const double new_roll = r.N() * 3.0 * kRadPerDeg, new_pitch = r.N() * 3.0 * kRadPerDeg;
    const double roll0 = roll, pitch0 = pitch;
    for (std::size_t i = 0; i < n; ++i) {
      const double t = static_cast<double>(i) * dt;
      bool still = kind == "still";
      double vib = 0.0, speed = 0.0;
      if (kind == "still" && p == 0 && touch && t >= touch_at && t < touch_at + touch_s) {
        still = false;  // a hand on the frame: a jolt
        const double x = (t - touch_at) / touch_s;
        o_r = 4.0 * kRadPerDeg * std::sin(std::numbers::pi * x) * std::sin(9.0 * t);
        o_p = 3.0 * kRadPerDeg * std::sin(std::numbers::pi * x) * std::cos(7.0 * t);
        acc = {0.8 * std::sin(20.0 * t), 0.6 * std::cos(17.0 * t), 0.0};
        touched = true;
      } else if (kind == "carry") {
        const double blend = std::clamp((t - (ph[p].s - 2.0)) / 2.0, 0.0, 1.0);
        if (blend <= 0.0) {  // walking: the frame swings, the steps bounce it
          o_r = Ou(o_r, 0.8, 8.0 * kRadPerDeg, dt, r), o_p = Ou(o_p, 0.8, 8.0 * kRadPerDeg, dt, r);
          o_y = Ou(o_y, 3.0, 30.0 * kRadPerDeg, dt, r);
          const double step = std::sin(2.0 * std::numbers::pi * 1.8 * t);
          acc = {Ou(acc[0], 0.5, 0.8, dt, r), Ou(acc[1], 0.5, 0.8, dt, r), 1.5 * step};
        } else {  // set down over the last 2 s at a new tilt
          o_r *= 0.95, o_p *= 0.95, o_y *= 0.95;
          for (double& v : acc) v *= 0.9;
        }
        roll = roll0 + (new_roll - roll0) * blend, pitch = pitch0 + (new_pitch - pitch0) * blend;
      } else if (kind == "fly") {
        o_r = Ou(o_r, man_tau, man_sd, dt, r), o_p = Ou(o_p, man_tau, man_sd, dt, r);
        o_y = Ou(o_y, 4.0 * man_tau, 90.0 * kRadPerDeg, dt, r);
        for (double& v : acc) v = Ou(v, 2.0, 1.5, dt, r);
        vib = 1.0, speed = std::clamp(0.5 + 0.5 * std::hypot(o_r, o_p) / man_sd, 0.0, 1.0);
      } else if (kind == "armed" || kind == "landed") {
        o_r *= 0.98, o_p *= 0.98, acc = {0.0, 0.0, 0.0};
        vib = 0.5;
      } else {
        if (touched) roll += 0.3 * kRadPerDeg * r.N(), touched = false;  // the touch left it 0.3 deg off
        o_r *= 0.8, o_p *= 0.8, o_y *= 0.8, acc = {0.0, 0.0, 0.0};
      }
      m.roll.push_back(roll + o_r), m.pitch.push_back(pitch + o_p), m.yaw.push_back(yaw + o_y);
      m.lin_acc_ned.push_back(acc);
      m.vibration.push_back(vib), m.speed.push_back(speed);
      m.armed.push_back(kind == "armed" || kind == "fly" || kind == "landed");
      m.landed.push_back(kind != "fly");
      m.still.push_back(still && std::abs(o_r) < 1e-6 && std::abs(o_p) < 1e-6);
    }
  }
  // The attitude states decay geometrically into a still phase: a row whose attitude still
  // changes is not still.
  for (std::size_t i = 1; i < m.still.size(); ++i)
    if (m.still[i] && (std::abs(m.roll[i] - m.roll[i - 1]) > 1e-7 || std::abs(m.pitch[i] - m.pitch[i - 1]) > 1e-7 ||
                       std::abs(m.yaw[i] - m.yaw[i - 1]) > 1e-7))
      m.still[i] = false;
  return m;
}

// 3x3 rotation NED <- body for ZYX Euler angles.
using M3 = std::array<std::array<double, 3>, 3>;
M3 Rot(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll), sr = std::sin(roll), cp = std::cos(pitch), sp = std::sin(pitch), cy = std::cos(yaw),
               sy = std::sin(yaw);
  return {{{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
           {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
           {-sp, cp * sr, cp * cr}}};
}

// One generator-2 power-on of the board (flight or chamber): ambient(t), the motion, the state.
// `warm_start`: the board and dies start at their self-heated equilibrium (a restart), else at
// the ambient.
std::vector<FlightRun> Gen2Run(const Gen2Board& b, const Truth& truth, const Motion& m, const std::function<double(double)>& ambient,
                               double fs, Rng& r, bool warm_start = false) {
  const std::size_t n = m.roll.size();
  const double dt = 1.0 / fs;
  // Body rates from the attitude: omega = vee(R_i^T R_{i+1} - R_{i+1}^T R_i) / (2 dt).
  std::vector<std::array<double, 3>> w(n), f(n);
  for (std::size_t i = 0; i < n; ++i) {
    const M3 R = Rot(m.roll[i], m.pitch[i], m.yaw[i]);
    const std::size_t j = std::min(i + 1, n - 1), h = i > 0 ? i - 1 : 0;
    const M3 A = Rot(m.roll[h], m.pitch[h], m.yaw[h]), B = Rot(m.roll[j], m.pitch[j], m.yaw[j]);
    M3 D{};
    for (int x = 0; x < 3; ++x)
      for (int y = 0; y < 3; ++y)
        for (int z = 0; z < 3; ++z) D[x][y] += A[z][x] * B[z][y];  // A^T B
    const double span = static_cast<double>(j - h) * dt;
    w[i] = span > 0 ? std::array<double, 3>{(D[2][1] - D[1][2]) / (2 * span), (D[0][2] - D[2][0]) / (2 * span), (D[1][0] - D[0][1]) / (2 * span)}
                    : std::array<double, 3>{0, 0, 0};
    const std::array<double, 3> sf_ned = {m.lin_acc_ned[i][0], m.lin_acc_ned[i][1], m.lin_acc_ned[i][2] - kG};
    for (int x = 0; x < 3; ++x) f[i][x] = R[0][x] * sf_ned[0] + R[1][x] * sf_ned[1] + R[2][x] * sf_ned[2];
  }
  // Vibration of this flight: three aliased motor tones and AR(1) noise, shared by the IMUs.
  const double vib_g = r.U(0.3, 4.0) * kRadPerDeg, vib_a = r.U(0.3, 3.0), pole = r.U(0.6, 0.95);
  std::array<double, 3> tone_hz{}, tone_ph{};
  for (int q = 0; q < 3; ++q) tone_hz[q] = r.U(3.0, 0.48 * fs), tone_ph[q] = r.U(0.0, 6.283);
  std::vector<std::array<double, 6>> vib(n);
  std::array<double, 6> ar{};
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * dt;
    for (int c = 0; c < 6; ++c) {
      ar[c] = pole * ar[c] + std::sqrt(1.0 - pole * pole) * r.N();
      double tones = 0.0;
      for (int q = 0; q < 3; ++q) tones += std::sin(2.0 * std::numbers::pi * tone_hz[q] * (1.0 + 0.05 * m.speed[i]) * t + tone_ph[q] + c);
      vib[i][c] = m.vibration[i] * (0.6 * ar[c] + 0.5 * tones) * (c < 3 ? vib_g : vib_a);
    }
  }
  // Board node (shared) and, per IMU, the die node, the MEMS structure's two lags.
  std::vector<double> board(n);
  double tb = ambient(0.0) + (warm_start ? b.board_heat_c : 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double eq = ambient(static_cast<double>(i) * dt) + b.board_heat_c / (1.0 + b.airflow * m.speed[i]);
    const double tau = b.board_tau_s / (1.0 + 2.0 * m.speed[i]);
    tb += (eq - tb) * dt / tau;
    board[i] = tb;
  }
  std::vector<FlightRun> out;
  for (int k = 0; k < kImus; ++k) {
    const Gen2Imu& g = b.imu[static_cast<std::size_t>(k)];
    FlightRun run = EmptyRun(n, fs);
    std::array<double, 3> g_off, a_off, g_wander{}, a_wander{};
    for (int a = 0; a < 3; ++a) g_off[a] = r.N() * 0.05 * kRadPerDeg, a_off[a] = r.N() * 0.020 * kG;
    double td = board[0] + (warm_start ? g.heat_share * b.die_heat_c : 0.0), l1 = td, l2 = td;
    const double k1 = 1.0 - std::exp(-dt / g.lag1_s), k2 = 1.0 - std::exp(-dt / g.lag2_s);  // exact first-order steps
    const double a_w = std::exp(-dt / g.wander_tau_s), s_w = std::sqrt(1.0 - a_w * a_w);
    for (std::size_t i = 0; i < n; ++i) {
      td += (board[i] + g.heat_share * b.die_heat_c / (1.0 + b.airflow * m.speed[i]) - td) * dt / g.die_tau_s;
      l1 += (td - l1) * k1;
      l2 += (l1 - l2) * k2;  // the MEMS structure: second order behind the thermometer
      run.temp_c[i] = td + 0.02 * r.N();
      for (int a = 0; a < 3; ++a) {
        g_wander[a] = a_w * g_wander[a] + s_w * g.gyro_wander_dps * kRadPerDeg * r.N();
        a_wander[a] = a_w * a_wander[a] + s_w * g.accel_wander_m_s2 * r.N();
        run.gyro_rad_s[a][i] = w[i][a] + vib[i][a] + truth.gyro[k][a](l2) + g_off[a] + g_wander[a] + r.N() * g.gyro_noise_dps * kRadPerDeg;
        run.accel_m_s2[a][i] = f[i][a] + vib[i][3 + a] + truth.accel[k][a](l2) + a_off[a] + a_wander[a] + r.N() * g.accel_noise_m_s2;
      }
    }
    run.armed = m.armed, run.landed = m.landed, run.truly_still = m.still;
    out.push_back(std::move(run));
  }
  return out;
}

Motion StillMotion(std::size_t n, Rng& r) {
  Motion m;
  const double roll = r.N() * 2.0 * kRadPerDeg, pitch = r.N() * 2.0 * kRadPerDeg;
  m.roll.assign(n, roll), m.pitch.assign(n, pitch), m.yaw.assign(n, 0.3);
  m.lin_acc_ned.assign(n, {0.0, 0.0, 0.0});
  m.vibration.assign(n, 0.0), m.speed.assign(n, 0.0);
  m.armed.assign(n, false), m.landed.assign(n, true), m.still.assign(n, true);
  return m;
}

// ---- scoring the true curve's least-squares cubic like `calibrate --validation` -------------
// The least-squares cubic of f over [lo, hi] (201 equal steps), about the middle (PX4's TREF).
gyrocomp::TemperatureCubic LsqCubic(const Curve& f, double lo, double hi) {
  gyrocomp::TemperatureCubic c;
  c.ref_temp_c = 0.5 * (lo + hi), c.temp_min_c = lo, c.temp_max_c = hi;
  const double s = std::max(0.5 * (hi - lo), 1e-6);
  double A[4][5] = {};
  for (int i = 0; i <= 200; ++i) {
    const double T = lo + (hi - lo) * i / 200.0, u = (T - c.ref_temp_c) / s;
    const double x[4] = {1.0, u, u * u, u * u * u};
    for (int p = 0; p < 4; ++p) {
      for (int q = 0; q < 4; ++q) A[p][q] += x[p] * x[q];
      A[p][4] += x[p] * f(T);
    }
  }
  for (int p = 0; p < 4; ++p) {  // Gauss-Jordan (the system is small and well conditioned)
    for (int q = 0; q < 4; ++q) {
      if (q == p) continue;
      const double k = A[q][p] / A[p][p];
      for (int z = 0; z < 5; ++z) A[q][z] -= k * A[p][z];
    }
  }
  for (int p = 0; p < 4; ++p) c.coeff[static_cast<std::size_t>(p)] = A[p][4] / A[p][p] / std::pow(s, p);
  return c;
}

struct Range {
  double lo = 1e9, hi = -1e9;
};

// The scores on one written held-out log of no correction and of the LS cubic, per sensor (gyro
// IMU 0..2, accel IMU 0..2) and axis, as calibrate --validation computes them (1 s means read,
// 10 s blocks, PX4 formula, the first temperature as the calibration temperature).
std::string ScoreHeldOut(const std::string& path, const Truth& truth, const std::array<Range, kImus>& range) {
  gyrocomp::ULogReadOptions ro;
  ro.average_window_us = 1000000;
  gyrocomp::Result<gyrocomp::ULogContents> log = gyrocomp::ReadULog(path, ro);
  if (!log.ok()) {
    std::fprintf(stderr, "%s\n", log.error().message.c_str());
    std::exit(1);
  }
  std::string json;
  auto score = [&](const char* type, std::uint32_t id, const std::vector<std::uint64_t>& t_us, const std::vector<double>& temp,
                   const std::array<const std::vector<double>*, 3>& v) {
    int imu = -1;
    for (int k = 0; k < kImus; ++k)
      if (id == (type[0] == 'g' ? gyrocomp::BoardGyroDeviceId(k) : gyrocomp::BoardAccelDeviceId(k))) imu = k;
    const double fs = static_cast<double>(t_us.size() - 1) / (static_cast<double>(t_us.back() - t_us.front()) * 1e-6);
    const auto block = static_cast<std::size_t>(std::max(1.0, std::round(10.0 * fs)));
    std::string raw, lsq;
    for (int a = 0; a < 3; ++a) {
      const Curve& f = type[0] == 'g' ? truth.gyro[imu][a] : truth.accel[imu][a];
      const gyrocomp::TemperatureCubic c = LsqCubic(f, range[imu].lo, range[imu].hi);
      const std::vector<double> fw = gyrocomp::FirmwareCorrection(gyrocomp::FirmwareFormula::kPx4, c, temp, temp.front());
      const std::vector<double> zero(temp.size(), 0.0);
      char buf[64];
      std::snprintf(buf, sizeof buf, "%s%.9g", a ? ", " : "", *gyrocomp::ResidualBlockRms(*v[a], zero, block));
      raw += buf;
      std::snprintf(buf, sizeof buf, "%s%.9g", a ? ", " : "", *gyrocomp::ResidualBlockRms(*v[a], fw, block));
      lsq += buf;
    }
    json += std::string(json.empty() ? "" : ", ") + "{\"type\": \"" + type + "\", \"imu\": " + std::to_string(imu) +
            ", \"device_id\": " + std::to_string(id) + ", \"raw\": [" + raw + "], \"lsq\": [" + lsq + "]}";
  };
  for (const auto& g : log->gyros) score("gyro", *g.device_id, g.timestamp_us, g.temperature_c, {&g.x_rad_s, &g.y_rad_s, &g.z_rad_s});
  for (const auto& a : log->accels) score("accel", *a.device_id, a.timestamp_us, a.temperature_c, {&a.x_m_s2, &a.y_m_s2, &a.z_m_s2});
  return "[" + json + "]";
}

void Write(const std::string& path, const std::vector<FlightRun>& imus, const std::vector<int>& order) {
  gyrocomp::Result<std::string> bytes = gyrocomp::EncodeFlightULog(imus, 1, order);
  if (!bytes.ok()) {
    std::fprintf(stderr, "%s\n", bytes.error().message.c_str());
    std::exit(1);
  }
  std::ofstream(path, std::ios::binary).write(bytes->data(), static_cast<std::streamsize>(bytes->size()));
}

// The truly still intervals of a run in log time (EncodeFlightULog: logging starts at 1 s),
// each [first row, last row + 1 / fs, then per IMU the lowest and highest logged temperature].
std::string StillIntervals(const std::vector<FlightRun>& imus, double fs) {
  const FlightRun& r = imus.front();
  std::string out;
  for (std::size_t i = 0; i < r.truly_still.size();) {
    if (!r.truly_still[i]) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < r.truly_still.size() && r.truly_still[j]) ++j;
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s[%.6f, %.6f", out.empty() ? "" : ", ", r.time_s[i] + 1.0, r.time_s[j - 1] + 1.0 + 1.0 / fs);
    out += buf;
    for (const FlightRun& m : imus) {
      const auto [lo, hi] = std::minmax_element(m.temp_c.begin() + static_cast<std::ptrdiff_t>(i), m.temp_c.begin() + static_cast<std::ptrdiff_t>(j));
      std::snprintf(buf, sizeof buf, ", %.4f, %.4f", *lo, *hi);
      out += buf;
    }
    out += "]";
    i = j;
  }
  return "[" + out + "]";
}

std::vector<int> Order(Rng& r, bool shuffle) {
  std::vector<int> o = {0, 1, 2};
  if (shuffle) std::shuffle(o.begin(), o.end(), r.e);
  return o;
}

// Generator 1's IMUs of one flight (SimulateFlight per IMU, seeds seed + i), each from the
// board's options with the flight's timing; `tweak` may change the options further. False with
// the message on stderr when the simulator refuses them.
bool Gen1Flight(const Gen1Board& b, double fs, double ambient_c, double still_before_s, double flight_s,
                double still_after_s, std::uint64_t seed, const std::function<void(gyrocomp::FlightSimOptions&)>& tweak,
                std::vector<FlightRun>* imus) {
  for (int i = 0; i < kImus; ++i) {
    gyrocomp::FlightSimOptions o = b.imu[static_cast<std::size_t>(i)];
    o.fs_hz = fs, o.ambient_c = ambient_c, o.still_before_s = still_before_s, o.flight_s = flight_s,
    o.still_after_s = still_after_s;
    if (tweak) tweak(o);
    o.seed = seed + static_cast<std::uint64_t>(i);
    gyrocomp::Result<FlightRun> run = gyrocomp::SimulateFlight(o);
    if (!run.ok()) {
      std::fprintf(stderr, "%s\n", run.error().message.c_str());
      return false;
    }
    imus->push_back(std::move(*run));
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s OUT_DIR GENERATOR(1|2) BOARD SEED [RATE_HZ=50]\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  const int gen = std::atoi(argv[2]), board = std::atoi(argv[3]);
  const auto seed = static_cast<std::uint64_t>(std::atoll(argv[4]));
  const double fs = argc > 5 ? std::atof(argv[5]) : 50.0;
  Rng r(seed * 1000003ULL + static_cast<std::uint64_t>(gen) * 101ULL + static_cast<std::uint64_t>(board));
  Truth truth;
  Gen1Board b1;
  Gen2Board b2;
  if (gen == 1) {
    b1 = MakeGen1Board(board);
    truth = Gen1Truth(b1);
  } else {
    b2 = MakeGen2Board(board, &truth, argc > 6 ? std::atof(argv[6]) : 1.0);
  }
  // Ambients spread over 0..35 C, in a shuffled order.
  std::vector<double> ambient(kFlights);
  for (int k = 0; k < kFlights; ++k) ambient[static_cast<std::size_t>(k)] = 35.0 * k / (kFlights - 1) + r.U(-1.5, 1.5);
  std::shuffle(ambient.begin(), ambient.end(), r.e);
  std::array<Range, kImus> range;
  // Ten ordinary flights, then three quick hops at one ambient (for the three-log check: too
  // little still time and change to identify a curve).
  std::string flights_json, quick_json;
  for (int k = 0; k < kFlights + 3; ++k) {
    std::vector<FlightRun> imus;
    const bool quick = k >= kFlights;
    const double amb = quick ? 20.0 + r.U(-1.0, 1.0) : ambient[static_cast<std::size_t>(k)];
    double pre_still_s = 0.0;
    if (gen == 1) {
      const double still_before = quick ? r.U(30.0, 60.0) : r.U(60.0, 600.0), flight = quick ? 300.0 : r.U(300.0, 1200.0),
                   after = quick ? r.U(20.0, 40.0) : r.U(120.0, 600.0);
      if (!Gen1Flight(b1, fs, amb, still_before, flight, after, r.e(), {}, &imus)) return 1;
      pre_still_s = still_before;
    } else {
      const Motion m = Gen2Timeline(fs, r, quick);
      const double drift_c_per_s = r.U(-1.0, 1.0) / 3600.0;  // outdoor air changing by up to 1 C an hour
      imus = Gen2Run(b2, truth, m, [=](double t) { return amb + drift_c_per_s * t; }, fs, r);
      std::size_t first_motion = 0;
      while (first_motion < m.still.size() && m.still[first_motion]) ++first_motion;
      pre_still_s = static_cast<double>(first_motion) / fs;
    }
    for (int i = 0; i < kImus && !quick; ++i)
      for (std::size_t j = 0; j < imus[static_cast<std::size_t>(i)].temp_c.size(); ++j)
        if (imus[0].truly_still[j]) {
          const double T = imus[static_cast<std::size_t>(i)].temp_c[j];
          range[i].lo = std::min(range[i].lo, T), range[i].hi = std::max(range[i].hi, T);
        }
    const std::vector<int> order = Order(r, gen == 2);
    const std::string name = quick ? "quick" + std::to_string(k - kFlights) + ".ulg" : "flight" + std::to_string(k) + ".ulg";
    Write(dir + "/" + name, imus, order);
    char head[256];
    std::snprintf(head, sizeof head, "{\"path\": \"%s\", \"ambient_c\": %.3f, \"power_on_still_s\": %.3f, \"rows\": %zu, \"order\": [%d, %d, %d], \"still\": ",
                  name.c_str(), amb, pre_still_s, imus[0].time_s.size(), order[0], order[1], order[2]);
    std::string& list = quick ? quick_json : flights_json;
    list += std::string(list.empty() ? "" : ",\n  ") + head + StillIntervals(imus, fs) + "}";
  }
  // The chamber runs: the dedicated calibration, then the held-out ones.
  std::string held_json;
  std::vector<ChamberProfile> runs = {kCalibration};
  runs.insert(runs.end(), kHeldOut.begin(), kHeldOut.end());
  for (std::size_t p = 0; p < runs.size(); ++p) {
    const ChamberProfile& prof = runs[p];
    std::vector<FlightRun> imus;
    if (gen == 1) {
      imus = Gen1Chamber(b1, truth, prof, fs, r);
    } else {
      const Motion m = StillMotion(static_cast<std::size_t>(prof.Duration() * fs), r);
      imus = Gen2Run(b2, truth, m, [prof](double t) { return prof.At(t); }, fs, r);
    }
    const std::string name = (p == 0 ? std::string("chamber_cal") : "heldout_" + prof.name) + ".ulg";
    Write(dir + "/" + name, imus, Order(r, gen == 2));
    if (p > 0)
      held_json += std::string(held_json.empty() ? "" : ",\n  ") + "{\"name\": \"" + prof.name + "\", \"path\": \"" + name +
                   "\", \"sensors\": " + ScoreHeldOut(dir + "/" + name, truth, range) + "}";
  }
  // Three restarts that barely warm (for the three-log check: still time enough, too little
  // change inside a log), from their own random stream so the logs above do not change.
  // Generator 1: a board that self-heats 2 C and cools 1.5 C in flight; generator 2: the same
  // board restarted at its self-heated temperature.
  Rng w(seed * 7777ULL + static_cast<std::uint64_t>(gen) * 13ULL + static_cast<std::uint64_t>(board));
  std::string warm_json;
  for (int k = 0; k < 3; ++k) {
    const double amb = 20.0 + w.U(-1.0, 1.0);
    std::vector<FlightRun> imus;
    if (gen == 1) {
      const double still_before = w.U(240.0, 360.0), after = w.U(120.0, 180.0);
      const auto barely_warms = [](gyrocomp::FlightSimOptions& o) { o.self_heating_c = 2.0, o.airflow_cooling_c = 1.5; };
      if (!Gen1Flight(b1, fs, amb, still_before, 120.0, after, w.e(), barely_warms, &imus)) return 1;
    } else {
      const Motion m = Gen2Timeline(fs, w, false, true);
      imus = Gen2Run(b2, truth, m, [=](double) { return amb; }, fs, w, /*warm_start=*/true);
    }
    const std::vector<int> order = Order(w, gen == 2);
    const std::string name = "warm" + std::to_string(k) + ".ulg";
    Write(dir + "/" + name, imus, order);
    char head[256];
    std::snprintf(head, sizeof head, "{\"path\": \"%s\", \"ambient_c\": %.3f, \"rows\": %zu, \"order\": [%d, %d, %d], \"still\": ",
                  name.c_str(), amb, imus[0].time_s.size(), order[0], order[1], order[2]);
    warm_json += std::string(warm_json.empty() ? "" : ",\n  ") + head + StillIntervals(imus, fs) + "}";
  }
  std::string ranges;
  for (int i = 0; i < kImus; ++i)
    ranges += (i ? ", " : "") + std::string("[") + std::to_string(range[i].lo) + ", " + std::to_string(range[i].hi) + "]";
  std::ofstream(dir + "/truth.json") << "{\"generator\": " << gen << ", \"board\": " << board << ", \"seed\": " << seed
                                     << ", \"rate_hz\": " << fs << ",\n \"flight_still_range_c\": [" << ranges
                                     << "],\n \"flights\": [" << flights_json << "],\n \"quick\": [" << quick_json << "],\n \"warm\": [" << warm_json
                                     << "],\n \"heldout\": [" << held_json << "]}\n";
  return 0;
}
