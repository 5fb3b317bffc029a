// The thermal-chamber experiment with ground truth (paper Section 4.1).
//
// A static (or moving, see TrueRateOptions) single-axis MEMS gyro in a temperature chamber:
//   chamber_temp_c(t)   piecewise-linear set-point schedule (ThermalProfileOptions)
//   sensor temp T(t)    first-order lag behind the chamber: dT/dt = (T_ch - T) / thermal_lag_s
//   temp_c              T + white measurement noise (temp_noise_c)
//   true_drift_dps      bias(T) polynomial + dT/dt coefficient * dT/dt + hysteresis (BiasModelOptions)
//   true_noise_dps      ARW (white) + bias instability (flicker, a sum of Gauss-Markov processes)
//                       + rate random walk + angle quantization (NoiseOptions)
//   rate_dps            true_rate_dps + true_drift_dps + true_noise_dps (then the optional output
//                       resolution rounding, whose error is part of true_noise_dps)
// Deterministic for a seed on every platform: std::mt19937_64 (fully specified by the standard)
// and our own normal generator (Marsaglia polar method), never std::normal_distribution.
// The model, its units and the flicker construction: docs/explanation/simulator.md.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "gyrocomp/io/io.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp {

// The chamber's set-point schedule. kHeatCool, kStairs and kRateCycles are calibration designs
// (`gyrocomp plan` compares profiles for a calibration: docs/reference/cli-contract.md).
enum class ThermalProfileKind {
  kPaper,  // paper Section 4.1: room hold, heat to hot, hold, 10 C steps down to cold, each held
  kSoak,   // constant at soak_temp_c for soak_duration_s
  kRamp,   // room hold, ramp to ramp_end_c at ramp_rate, hold
  kCycle,  // room hold, heat to hot, hold, cool to cold, hold, heat to room, hold; num_cycles times
  kHeatCool,  // cold soak (room_hold_s at cold), heat to hot, hold, cool to cold, hold: both
              // directions over the whole range with holds at both ends (6.3 h at 1 C/min)
  kStairs,    // cold soak, staircase up (steps of 2 step_c at ramp_rate), staircase down (offset
              // by step_c, at ramp_rate / 2), plateaus held hold_s / 2: holds and two ramp rates in
              // both directions (11.5 h with the defaults)
  kRateCycles,  // cold soak (room_hold_s / 2 at cold), 4 full-range cycles cold -> hot -> cold
                // with hold_s / 3 at both ends; cycles 1 and 3 heat at 2 ramp_rate and cool at
                // ramp_rate, 2 and 4 the reverse: many reversals and two rates each way (13.2 h);
                // the design of docs/explanation/drift-models.md "What any estimator can reach"
  kUser,      // the user's chamber schedule: user_time_s / user_temp_c (simulate --profile-csv)
};
// "paper" | "soak" | "ramp" | "cycle" | "heat-cool" | "stairs" | "rate-cycles" | "user".
std::optional<ThermalProfileKind> ParseThermalProfileKind(const std::string& name);
// ThermalProfileKind -> "paper" | "soak" | ... (the names ParseThermalProfileKind accepts).
const char* ThermalProfileKindName(ThermalProfileKind kind);

// The chamber schedule: its kind and the temperatures, holds and rates it is built from.
struct ThermalProfileOptions {
  ThermalProfileKind kind = ThermalProfileKind::kPaper;  // the paper's run by default
  // Room (start) temperature, deg C. Paper: "room temperature", 1 h powered on.
  double room_temp_c = 25.0;
  double room_hold_s = 3600.0;  // time held at room_temp_c first, s (paper: 1 h)
  // Hot and cold extremes, deg C (paper: 60 C and -40 C).
  double hot_temp_c = 60.0;
  double cold_temp_c = -40.0;  // cold extreme, deg C
  // Step size of the staircase down from hot to cold, deg C (paper: 10 C). Must be > 0.
  double step_c = 10.0;
  // Hold at each plateau (hot, every step, cold), s (paper: 1 h).
  double hold_s = 3600.0;
  // Chamber slew rate between plateaus, deg C per minute (the paper says only "quickly";
  // 1 C/min gives a 14.3 h paper run). Must be > 0.
  double ramp_rate_c_per_min = 1.0;
  // kSoak: temperature and duration.
  double soak_temp_c = 25.0;
  double soak_duration_s = 7200.0;  // kSoak: duration, s
  // kRamp: end temperature (start is room_temp_c).
  double ramp_end_c = 60.0;
  // kCycle: number of hot-cold-room cycles. Must be >= 1.
  int num_cycles = 1;
  // kUser: chamber set point at these times (s, strictly increasing, first >= 0; linear in
  // between, held before the first and after the last), deg C. At least 2 points.
  std::vector<double> user_time_s, user_temp_c;  // set point at each user_time_s, deg C
  // Returns false and a message naming the field when an option is out of range.
  bool IsValid(std::string* error) const;
};

// The chamber set point as a piecewise-linear function of time.
struct ThermalSchedule {
  std::vector<double> time_s;  // breakpoints, strictly increasing, time_s[0] = 0
  std::vector<double> temp_c;  // chamber temperature at each breakpoint
  double duration_s() const { return time_s.empty() ? 0.0 : time_s.back(); }  // last breakpoint, s
  // Linear interpolation; clamps outside [0, duration].
  double ChamberTempC(double t_s) const;
};
// The schedule of `options`. Errors: invalid options (kInvalidArgument).
Result<ThermalSchedule> MakeThermalSchedule(const ThermalProfileOptions& options);

// Deterministic bias (drift) as a function of the sensor temperature and its history.
struct BiasModelOptions {
  // bias(T) = sum_k poly_dps[k] * (T - reference_temp_c)^k, deg/s per C^k. Default: a cubic,
  // -0.03 .. +0.09 deg/s over the paper run's -40..60 C (all terms together).
  double reference_temp_c = 25.0;
  std::vector<double> poly_dps = {0.02, 1.5e-3, 1.2e-5, -2.0e-7};  // coefficients, k = 0, 1, ...
  // Term proportional to the sensor's temperature rate: deg/s per (deg C / s).
  double dtemp_coeff_dps_per_c_per_s = 1.5;
  // Hysteresis: coeff * (T - P(T)) where P is a play (backlash) operator of total width
  // hysteresis_width_c: the term is +coeff*width/2 while heating, -coeff*width/2 while cooling
  // (after a reversal of at least the width) and changes linearly in between. deg/s per deg C.
  double hysteresis_width_c = 4.0;
  double hysteresis_coeff_dps_per_c = 2.0e-3;  // coeff, deg/s per deg C
  // Returns false and a message naming the field when an option is out of range.
  bool IsValid(std::string* error) const;
};

// Stochastic error terms in datasheet units (IEEE Std 952). Zero switches a term off.
struct NoiseOptions {
  // Angle random walk N, deg/sqrt(h): sigma_ADEV(1 s) = N / 60 deg/s. Paper raw: 1.667.
  double arw_deg_per_sqrt_h = 1.667;
  // Bias instability B, deg/h: flicker floor of the ADEV = 0.664 B. The default (44 deg/h,
  // floor 29.2 deg/h) makes the ADEV minimum of the default paper run (drift included) about
  // 30 deg/h: 29.1 .. 30.6 over seeds 1-6, at tau 80-160 s.
  double bias_instability_deg_per_h = 44.0;
  // Flicker model: a sum of first-order Gauss-Markov processes, equal variances, correlation
  // times log-spaced from flicker_min_corr_s to flicker_max_corr_s with flicker_per_decade per
  // decade; the variance is set so the ADEV of the sum equals 0.664 B at the geometric middle of
  // the band (ripple about +-1% for 2 per decade). The floor is flat within 2% from 20x the
  // shortest to 1/6 of the longest correlation time; below, the flicker fades like a rate random
  // walk (so sigma(1 s) stays the ARW's). See docs/explanation/simulator.md.
  double flicker_min_corr_s = 10.0;
  double flicker_max_corr_s = 1.0e5;  // longest correlation time, s
  int flicker_per_decade = 2;         // processes per decade of correlation time
  // Rate random walk K, deg/h/sqrt(h): sigma_ADEV(tau) = K sqrt(tau / 3).
  double rrw_deg_per_h_per_sqrt_h = 3.0;
  // Angle quantization Q, deg (IEEE 952: sigma_ADEV(tau) = sqrt(3) Q / tau): the integrated angle
  // is rounded to multiples of Q*sqrt(12) before differentiation. 0 = off.
  double quantization_deg = 0.0;
  // Output resolution (LSB) of rate_dps, deg/s: the output is rounded to multiples of it. 0 = off.
  double resolution_dps = 0.0;
  // Returns false and a message naming the field when an option is out of range.
  bool IsValid(std::string* error) const;
};

// The real angular rate applied to the gyro (truth the later stages must preserve). Terms add.
struct TrueRateOptions {
  // Constant rate, deg/s (e.g. the Earth rate component on the axis, 15.04 deg/h * sin(lat)).
  double constant_dps = 0.0;
  // Steps: a rate pattern 0, +A, 0, -A, ... each held step_period_s. A = 0: off.
  double step_amplitude_dps = 0.0;
  double step_period_s = 600.0;  // how long each step is held, s
  // Sinusoid A sin(2 pi f t). A = 0: off.
  double sine_amplitude_dps = 0.0;
  double sine_frequency_hz = 0.01;  // f, Hz
  // Returns false and a message naming the field when an option is out of range.
  bool IsValid(std::string* error) const;
};

// One simulated chamber run: sample rate, seed, profile, thermal lag and the error terms.
struct SimulatorOptions {
  // Output sample rate, Hz.
  double fs_hz = 100.0;
  // Seed of the generator (std::mt19937_64). Same options + seed -> bit-identical output.
  std::uint64_t seed = 1;
  // Record length. nullopt: the profile's own duration. Longer: the last temperature is held.
  std::optional<double> duration_s;
  ThermalProfileOptions profile;  // chamber schedule (the paper's by default)
  // First-order thermal lag of the sensor behind the chamber, s. 0: no lag.
  double thermal_lag_s = 600.0;
  // White noise of the temperature reading, deg C (1 sigma). 0: exact.
  double temp_noise_c = 0.01;
  BiasModelOptions bias;     // deterministic drift
  NoiseOptions noise;        // stochastic terms
  TrueRateOptions true_rate;  // applied rate (0 by default: a static gyro)
  // Checks every nested options struct too; the message names the field.
  bool IsValid(std::string* error) const;
};

// What a run holds, in figures.
struct SimulationSummary {
  std::size_t num_samples = 0;  // N
  double duration_s = 0.0;      // N / fs_hz, s
  double seconds = 0.0;  // wall time
  // Sensor temperature range (true, noise-free), deg C: lowest.
  double min_temp_c = 0.0, max_temp_c = 0.0;          // highest sensor temperature, deg C
  // True drift range, deg/s: lowest.
  double min_drift_dps = 0.0, max_drift_dps = 0.0;    // highest true drift, deg/s
  double flicker_process_sigma_dps = 0.0;             // sigma of each Gauss-Markov process
  int num_flicker_processes = 0;  // Gauss-Markov processes summed for the flicker
  // "simulated N samples (.. h) in .. s; sensor temperature .. C; true drift ..; flicker: .."
  std::string BriefReport() const;
};

// The columns of a simulated run, sample by sample, with the ground truth.
struct SimulatedRun {
  double fs_hz = 0.0;  // sample rate, Hz
  std::vector<double> time_s;           // i / fs
  std::vector<double> rate_dps;         // what the gyro outputs
  std::vector<double> temp_c;           // what the temperature sensor outputs
  std::vector<double> chamber_temp_c;   // chamber set point
  std::vector<double> sensor_temp_c;    // true sensor temperature (noise-free)
  std::vector<double> true_rate_dps;    // applied rate
  std::vector<double> true_drift_dps;   // deterministic temperature-dependent bias
  std::vector<double> true_noise_dps;   // rate - true_rate - true_drift (all stochastic terms)
  SimulationSummary summary;  // ranges and counts of the run
  std::size_t num_samples() const { return time_s.size(); }  // N
  // Columns in this order: time_s, rate_dps, temp_c, chamber_temp_c, sensor_temp_c,
  // true_rate_dps, true_drift_dps, true_noise_dps. The && overload moves the columns out (no
  // copy of 8 x N doubles: 330 MB for the paper run at 100 Hz).
  Table ToTable() const&;
  Table ToTable() &&;  // the same, moving the columns out
};

// Runs the chamber experiment of `options`. Errors: invalid options (kInvalidArgument).
Result<SimulatedRun> Simulate(const SimulatorOptions& options = {});

// Theoretical ADEV (deg/s) at tau_s of the stochastic terms of `noise` (no drift, no true rate):
// white + Gauss-Markov sum (exact continuous-time formula) + RRW + quantization, added in
// variance. Used by tests and docs to check the simulator against theory.
double ModelAdevDps(const NoiseOptions& noise, double tau_s);

// Standard deviation (deg/s) of each flicker Gauss-Markov process and their correlation times (s)
// for `noise` (empty when bias_instability is 0).
struct FlickerModel {
  std::vector<double> corr_time_s;  // correlation time of each process, s
  double process_sigma_dps = 0.0;   // SD of each process, deg/s
};
// The flicker processes of `noise` (NoiseOptions' flicker construction).
FlickerModel MakeFlickerModel(const NoiseOptions& noise);

// ---- Accelerometers and whole boards -----------------------------------------------------------
// One mechanism, many sensors: an accelerometer axis is the same chamber experiment (thermal
// profile, lag, temperature noise, bias polynomial in T, dT/dt term, flicker from Gauss-Markov
// processes) on specific force in m/s^2, with datasheet noise units mapped one to one: velocity
// random walk VRW (m/s/sqrt(h), sigma_ADEV(1 s) = VRW / 60 m/s^2) in place of the ARW, bias
// instability in m/s^2 (flicker floor 0.664 B) in place of deg/h, no hysteresis, no rate random
// walk; plus a constant (gravity on the axis that points up: -9.80665 m/s^2 on z for a board lying
// flat, FRD axes as PX4 and ArduPilot log them).
struct AccelAxisOptions {
  double reference_temp_c = 25.0;  // temperature of the polynomial's origin, deg C
  // bias(T) = sum_k bias_poly_m_s2[k] (T - reference_temp_c)^k, m/s^2 per C^k (default: about
  // 0.06 m/s^2 over 25..60 C, MEMS-typical).
  std::vector<double> bias_poly_m_s2 = {0.02, 1.5e-3, 1.0e-5, -1.0e-7};
  double dtemp_coeff_m_s2_per_c_per_s = 0.0;  // dT/dt term, m/s^2 per (deg C / s); 0: none
  double vrw_m_s_per_sqrt_h = 0.06;       // ~ 100 ug/sqrt(Hz)
  double bias_instability_m_s2 = 4.0e-4;  // ~ 40 ug
  double constant_m_s2 = 0.0;             // gravity component on this axis
  // Returns false and a message naming the field when an option is out of range.
  bool IsValid(std::string* error) const;
};
// The columns of one simulated accelerometer axis.
struct AccelAxisRun {
  std::vector<double> time_s,  // i / fs, s
      accel_m_s2,              // what the accelerometer outputs, m/s^2
      temp_c,                  // what the temperature sensor outputs, deg C
      true_bias_m_s2;          // deterministic temperature-dependent bias, m/s^2
};
// `chamber` gives the profile, rate, lag, seed and temperature noise (its gyro bias and noise
// are not used).
Result<AccelAxisRun> SimulateAccelAxis(const SimulatorOptions& chamber, const AccelAxisOptions& accel);

// A flight-controller board in the chamber: `num_imus` IMUs (gyro x, y, z and accel x, y, z each;
// every axis its own seed and its own drift: the chamber's gyro polynomial and the accel
// polynomial scaled by a per-axis factor), one barometer (pressure drift in Pa vs T, white noise).
struct BoardSimOptions {
  SimulatorOptions chamber;  // profile, rate, lag, seed; gyro drift (scaled per axis) and noise
  int num_imus = 3;          // 1..4
  AccelAxisOptions accel;    // accel terms (bias polynomial scaled per axis, gravity on z)
  bool with_baro = true;     // simulate the barometer
  std::vector<double> baro_poly_pa = {0.0, -3.0, 0.02};  // Pa per C^k about reference_temp_c
  double baro_noise_pa = 2.0;          // white noise of the pressure, Pa (1 sigma), >= 0
  double baro_pressure_pa = 101325.0;  // constant pressure the drift and noise add to, Pa
  // Returns false and a message naming the field ("BoardSimOptions::num_imus = 5: must be 1..4").
  bool IsValid(std::string* error) const;
};
// The columns of one IMU of a board (axes x, y, z in the sensor frame, FRD).
struct BoardImuRun {
  std::vector<double> temp_c;  // the IMU's temperature reading, deg C
  std::array<std::vector<double>, 3> gyro_rad_s,  // gyro output per axis, rad/s
      accel_m_s2;                                 // accel output per axis, m/s^2
  std::array<std::vector<double>, 3> true_gyro_drift_rad_s,  // true gyro drift per axis, rad/s
      true_accel_bias_m_s2;  // true accel bias per axis (without gravity), m/s^2
};
// A simulated board: a shared time base, the IMUs and the barometer.
struct BoardRun {
  double fs_hz = 0.0;             // sample rate, Hz
  std::vector<double> time_s;     // i / fs, s
  std::vector<BoardImuRun> imus;  // num_imus IMUs
  // Barometer pressure, Pa (empty without a barometer).
  std::vector<double> baro_pressure_pa, baro_temp_c;  // its temperature (IMU 0's), deg C
};
// Simulates every IMU axis and the barometer. Errors: invalid options (kInvalidArgument).
Result<BoardRun> SimulateBoard(const BoardSimOptions& options);
// The per-axis scale of the drift of IMU `imu`, axis `axis` (0..2; signs alternate so axes differ).
double BoardAxisDriftScale(int imu, int axis);

// The board as the autopilots log it (so their own scripts read it):
// PX4 ULog: sensor_gyro / sensor_accel multi_id k per IMU (float32; gyro and accel of one IMU
// share its device id, realistic PX4 ids: SPI ICM20689, ICM20602, BMI055 gyro/accel, ...),
// sensor_baro multi_id 0 (MS5611, Pa), TC_G/TC_A/TC_B_ENABLE = 0.
// ArduPilot DataFlash: IMU rows with I and T, rotated to the board frame by `ahrs_orientation`
// (AHRS_ORIENTATION written as a PARM), INS_TCALn_ENABLE = 0, no barometer.
// Both are sampled at `log_rate_hz` (<= the simulation rate; every k-th sample).
Result<std::string> EncodeBoardULog(const BoardRun& board, double log_rate_hz);
// The ArduPilot DataFlash log described above.
Result<std::string> EncodeBoardDataFlash(const BoardRun& board, double log_rate_hz, int ahrs_orientation);
// The device ids EncodeBoardULog gives IMU `imu` (gyro, accel) and the barometer.
std::uint32_t BoardGyroDeviceId(int imu);
std::uint32_t BoardAccelDeviceId(int imu);  // the accel's device id of IMU `imu`
std::uint32_t BoardBaroDeviceId();  // the barometer's device id (MS5611 on SPI)

// Deterministic normal generator: Marsaglia polar method on std::mt19937_64 (53-bit uniforms).
// Portable: same sequence on every standard library.
class NormalGenerator {
 public:
  explicit NormalGenerator(std::uint64_t seed);  // seeds the std::mt19937_64
  double Next();  // N(0, 1)
  double Uniform();  // [0, 1)

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace gyrocomp
