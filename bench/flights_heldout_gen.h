// What bench/flights_heldout_gen.cc (generator 1, the scoring, main) and
// bench/flights_heldout_gen2.cc (generator 2) share: the board's truth, the chamber profiles,
// the random source and generator 2's entry points. Not part of the CMake build.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "gyrocomp/sim/flight.h"

namespace flights_heldout {

using gyrocomp::FlightRun;
inline constexpr double kG = 9.80665;
inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;
inline constexpr int kImus = 3;
inline constexpr int kFlights = 10;

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
inline const ChamberProfile kCalibration{"calibration", -5.0, 600.0, 1.0, 55.0, 600.0};
// Held out: heating, cooling and a warm-up over the flights' ambients (0..35 C), and a heating
// to 55 C that goes beyond the temperatures the flights reach.
inline const std::vector<ChamberProfile> kHeldOut = {{"heating", 0.0, 1200.0, 0.5, 35.0, 300.0},
                                              {"cooling", 35.0, 1200.0, 0.5, 0.0, 300.0},
                                              {"warm-up", 15.0, 2400.0, 1.0, 15.0, 0.0},
                                              {"wide-heating", 5.0, 1200.0, 0.8, 55.0, 300.0}};

inline FlightRun EmptyRun(std::size_t n, double fs) {
  FlightRun r;
  r.time_s.resize(n), r.temp_c.resize(n);
  for (auto& v : r.gyro_rad_s) v.resize(n);
  for (auto& v : r.accel_m_s2) v.resize(n);
  r.armed.assign(n, false), r.landed.assign(n, true), r.truly_still.assign(n, true);
  for (std::size_t i = 0; i < n; ++i) r.time_s[i] = static_cast<double>(i) / fs;
  return r;
}

// Gravity's specific force in the sensor frame (FRD) at roll / pitch (rad): R^T (0, 0, -g).
inline std::array<double, 3> GravityFrd(double roll, double pitch) {
  return {kG * std::sin(pitch), -kG * std::sin(roll) * std::cos(pitch), -kG * std::cos(roll) * std::cos(pitch)};
}

// ---- generator 2 (flights_heldout_gen2.cc) ----------------------------------------------------
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

// What happens to the vehicle at each row: the phases' effect on motion, state and airflow.
struct Motion {
  std::vector<double> roll, pitch, yaw;  // rad
  std::vector<std::array<double, 3>> lin_acc_ned;  // m/s^2, besides gravity
  std::vector<double> vibration;  // 0 off, else motor on (scale of the per-flight amplitude)
  std::vector<double> speed;  // airflow, 0..1
  std::vector<bool> armed, landed, still;
};

// A generator-2 board: its IMUs' thermal nodes and noise, and its static curves into `truth`
// (`lag_scale` multiplies the MEMS lag behind the die thermometer; 0: none).
Gen2Board MakeGen2Board(int board, Truth* truth, double lag_scale);
// The flight's timeline: power-on still (a touch in it, sometimes), carried to the take-off spot,
// still again, armed on the ground, flight, landed armed, still, sometimes picked up at the end.
// `quick`: a short hop (at most a minute still at each end, five minutes in the air). `warm`: a
// restart of a warm board (4..6 min still, two minutes in the air, 2..3 min still).
Motion Gen2Timeline(double fs, Rng& r, bool quick, bool warm = false);
// One generator-2 power-on of the board (flight or chamber): ambient(t), the motion, the state.
// `warm_start`: the board and dies start at their self-heated equilibrium (a restart), else at
// the ambient.
std::vector<gyrocomp::FlightRun> Gen2Run(const Gen2Board& b, const Truth& truth, const Motion& m,
                                         const std::function<double(double)>& ambient, double fs, Rng& r,
                                         bool warm_start = false);
// A chamber run's motion: still on the shelf at a small fixed attitude.
Motion StillMotion(std::size_t n, Rng& r);

}  // namespace flights_heldout
