// An ordinary flight of a small vehicle as the IMU sees it, for the still detector's tests: power
// on at the ambient temperature, still on the ground while the board self-heats, armed (motors
// spinning: vibration, still on the ground), a flight with manoeuvres, vibration and airflow
// cooling, landing (motors still spinning a moment), disarmed and still again. Each power-on has
// its own constant offset (turn-on repeatability) and lands at its own small tilt (gravity in the
// sensor frame differs between the still parts). A thermal drift of the board's temperature
// (a cubic per axis, zero unless set) is added to the gyro and accelerometer. Ground truth: which
// samples are still, and the true drift (FlightGyroDriftRadS, FlightAccelDriftM_S2).
// EncodeFlightULog writes several IMUs of one board flying together as a PX4 ULog.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"

namespace gyrocomp {

// Settings of SimulateFlight: the phases' durations, the temperatures, the noise and motion.
struct FlightSimOptions {
  double fs_hz = 200.0;               // IMU rows per second
  double ambient_c = 20.0;            // air temperature at power-on, C
  double still_before_s = 300.0;      // still on the ground after power-on, s
  double armed_ground_s = 4.0;        // armed, motors spinning, before take-off, s
  double flight_s = 600.0;            // in the air, s
  double landed_armed_s = 3.0;        // on the ground again, motors spinning, s
  double still_after_s = 180.0;       // disarmed, still, s
  double self_heating_c = 15.0;       // board temperature rise over the ambient when still, C
  double self_heating_tau_s = 400.0;  // its time constant, s
  double airflow_cooling_c = 8.0;     // how far the airflow pulls the board down in flight, C
  double gyro_noise_dps = 0.02;       // white noise per sample, deg/s (1 sigma)
  double accel_noise_m_s2 = 0.02;     // white noise per sample, m/s^2 (1 sigma)
  double gyro_offset_dps = 0.05;      // per-power-on offset, 1 sigma per axis, deg/s
  double accel_offset_m_s2 = 0.196;   // per-power-on offset, 1 sigma per axis (20 mg), m/s^2
  double vibration_gyro_dps = 3.0;    // motor vibration on the gyro (1 sigma), deg/s
  double vibration_accel_m_s2 = 3.0;  // motor vibration on the accelerometer (1 sigma), m/s^2
  double manoeuvre_rate_dps = 60.0;   // manoeuvre body rates, amplitude, deg/s
  // True thermal drift: axis a gets axis_scale[a] * sum_k c[k] (T - drift_ref_c)^k, T the board
  // temperature (deg/s per C^k for the gyro, m/s^2 per C^k for the accelerometer).
  std::array<double, 4> gyro_drift_dps{};    // c0..c3 of the gyro drift, deg/s / C^k
  std::array<double, 4> accel_drift_m_s2{};  // c0..c3 of the accelerometer drift, m/s^2 / C^k
  std::array<double, 3> axis_scale = {1.0, -0.7, 0.5};  // per axis factor of both drifts
  double drift_ref_c = 25.0;  // reference temperature of the drift cubics, deg C
  double landed_tilt_deg = 2.0;  // attitude after landing, roll and pitch 1 sigma, deg
  std::uint64_t seed = 1;  // seed of the noise and offsets; the same seed gives the same run
  // False with the reason in `error` when a setting is out of range.
  bool IsValid(std::string* error) const;
};

// A simulated flight log with its ground truth, one entry per IMU row.
struct FlightRun {
  std::vector<double> time_s;  // s
  std::vector<double> temp_c;  // board temperature, deg C
  std::array<std::vector<double>, 3> gyro_rad_s;  // x, y, z angular rate, rad/s, sensor frame (FRD)
  std::array<std::vector<double>, 3> accel_m_s2;  // x, y, z specific force, m/s^2, sensor frame (FRD)
  std::vector<bool> armed;        // the log's armed state
  std::vector<bool> landed;       // the log's landed state
  std::vector<bool> truly_still;  // ground truth: disarmed on the ground, nothing moving
};

// Simulates one flight. Errors: invalid options (kInvalidArgument).
Result<FlightRun> SimulateFlight(const FlightSimOptions& options);

// The true thermal drift of gyro axis `axis` (0..2) at board temperature temp_c, rad/s.
double FlightGyroDriftRadS(const FlightSimOptions& options, int axis, double temp_c);
// The true thermal drift of accelerometer axis `axis` at temp_c, m/s^2.
double FlightAccelDriftM_S2(const FlightSimOptions& options, int axis, double temp_c);

// The IMUs of one board in one flight (imus[k]: the k-th IMU, same time base) as a PX4 ULog:
// sensor_gyro / sensor_accel multi_id k with the board simulator's device ids
// (BoardGyroDeviceId(k), BoardAccelDeviceId(k), simulator.h), float32, every `decimate`-th row;
// the first IMU's armed and landed state as actuator_armed.armed, vehicle_status.arming_state and
// vehicle_land_detected.landed (a row once a second and at every change, every row's time).
// `order` (empty: the identity) is the order in which the drivers enumerated the IMUs at this
// boot: multi_id k logs imus[order[k]] with that IMU's device ids (board_boot.h: the instance
// numbers change between power-ons, the device ids stay with the chip); the state topics are the
// first IMU's (imus[0]) whatever the order.
// Errors: no IMU, IMUs of different lengths, decimate < 1, `order` not a permutation of the IMUs
// (kInvalidArgument).
Result<std::string> EncodeFlightULog(const std::vector<FlightRun>& imus, int decimate = 1, const std::vector<int>& order = {});

}  // namespace gyrocomp
