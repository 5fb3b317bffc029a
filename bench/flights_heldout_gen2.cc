// Generator 2 of bench/flights_heldout_gen.cc, written apart from src/sim/flight.cc: a two-node
// board (board and die, airflow cooling in flight) whose logged temperature is the die
// thermometer, the MEMS structure lagging it by a second-order lag; curves that are not cubics;
// a Gauss-Markov bias wander; attitude from smooth Euler-angle processes; motor vibration;
// disarmed handling the log's armed / landed state does not show (flights_heldout_gen.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "flights_heldout_gen.h"

namespace flights_heldout {

namespace {

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

}  // namespace

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


namespace {

// An Ornstein-Uhlenbeck step: x relaxes to 0 with tau, driven to stationary sd sigma.
double Ou(double x, double tau, double sigma, double dt, Rng& r) {
  const double a = std::exp(-dt / tau);
  return a * x + sigma * std::sqrt(1.0 - a * a) * r.N();
}

}  // namespace

Motion Gen2Timeline(double fs, Rng& r, bool quick, bool warm) {
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

namespace {

// 3x3 rotation NED <- body for ZYX Euler angles.
using M3 = std::array<std::array<double, 3>, 3>;
M3 Rot(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll), sr = std::sin(roll), cp = std::cos(pitch), sp = std::sin(pitch), cy = std::cos(yaw),
               sy = std::sin(yaw);
  return {{{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
           {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
           {-sp, cp * sr, cp * cr}}};
}

}  // namespace

std::vector<gyrocomp::FlightRun> Gen2Run(const Gen2Board& b, const Truth& truth, const Motion& m, const std::function<double(double)>& ambient,
                               double fs, Rng& r, bool warm_start) {
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
  std::vector<gyrocomp::FlightRun> out;
  for (int k = 0; k < kImus; ++k) {
    const Gen2Imu& g = b.imu[static_cast<std::size_t>(k)];
    gyrocomp::FlightRun run = EmptyRun(n, fs);
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

}  // namespace flights_heldout
