// The chamber-experiment simulator: sensor thermal lag, temperature-dependent bias with rate and
// hysteresis terms, IEEE 952 noise terms. Model and units: docs/explanation/simulator.md.
#include "gyrocomp/sim/simulator.h"
#include "gyrocomp/sim/board_boot.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <utility>

#include "gyrocomp/core/units.h"
#include "gyrocomp/io/board_rotation.h"
#include "gyrocomp/io/dataflash.h"
#include "gyrocomp/io/ulog.h"

namespace gyrocomp {
namespace {

// Allan variance at tau of a first-order Gauss-Markov process with unit variance and correlation
// time T (continuous time, autocovariance exp(-|t|/T)):
//   sigma^2(tau) = (2T/tau) [1 - (T/(2 tau)) (3 - 4 e^{-tau/T} + e^{-2 tau/T})]
// (e.g. El-Sheimy, Hou & Niu, IEEE TIM 57(1) 2008). For tau << T it tends to 2 tau / (3T), a rate
// random walk; for tau >> T to 2T/tau, white noise. The bracket cancels for small x = tau/T, so
// a Taylor series is used there (next term x^4/12 < 1e-12 relative for x < 1e-3).
double GaussMarkovAvarUnit(double tau_s, double corr_s) {
  const double x = tau_s / corr_s;
  if (x < 1e-3) return 2.0 * x / 3.0 - x * x / 2.0 + 7.0 * x * x * x / 30.0;
  return (2.0 / x) * (1.0 - (3.0 - 4.0 * std::exp(-x) + std::exp(-2.0 * x)) / (2.0 * x));
}

// Angle random walk N (deg/sqrt(h)) -> deg/s*sqrt(s); RRW K (deg/h/sqrt(h)) -> deg/s/sqrt(s).
double ArwDpsSqrtS(const NoiseOptions& n) { return units::DegPerSqrtHourToDegPerSqrtSec(n.arw_deg_per_sqrt_h); }
double RrwDpsPerSqrtS(const NoiseOptions& n) { return units::DphPerSqrtHourToDpsPerSqrtSec(n.rrw_deg_per_h_per_sqrt_h); }

// Applied rate: constant + step pattern (0, +A, 0, -A, ...) + sinusoid.
double TrueRateDps(const TrueRateOptions& o, double t_s) {
  double r = o.constant_dps;
  if (o.step_amplitude_dps != 0.0) {
    const auto phase = static_cast<long long>(std::floor(t_s / o.step_period_s)) % 4;
    if (phase == 1) r += o.step_amplitude_dps;
    if (phase == 3) r -= o.step_amplitude_dps;
  }
  if (o.sine_amplitude_dps != 0.0) {
    r += o.sine_amplitude_dps * std::sin(2.0 * std::numbers::pi * o.sine_frequency_hz * t_s);
  }
  return r;
}

double Polynomial(const std::vector<double>& c, double x) {
  double y = 0.0;
  for (auto it = c.rbegin(); it != c.rend(); ++it) y = y * x + *it;  // Horner
  return y;
}

}  // namespace

// ---- normal generator ---------------------------------------------------------------------

NormalGenerator::NormalGenerator(std::uint64_t seed) : engine_(seed) {}

double NormalGenerator::Uniform() {
  // 53 random bits -> [0, 1) exactly representable (std::generate_canonical is not portable).
  return static_cast<double>(engine_() >> 11) * 0x1.0p-53;
}

double NormalGenerator::Next() {
  // Marsaglia polar method: (u, v) uniform in the unit disc -> two independent N(0, 1).
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double u, v, s;
  do {
    u = 2.0 * Uniform() - 1.0;
    v = 2.0 * Uniform() - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  const double f = std::sqrt(-2.0 * std::log(s) / s);
  spare_ = v * f;
  has_spare_ = true;
  return u * f;
}

// ---- noise model ----------------------------------------------------------------------------

FlickerModel MakeFlickerModel(const NoiseOptions& noise) {
  FlickerModel m;
  if (noise.bias_instability_deg_per_h <= 0.0) return m;
  // Correlation times log-spaced, flicker_per_decade per decade, spanning [min, max].
  const double decades = std::log10(noise.flicker_max_corr_s / noise.flicker_min_corr_s);
  const int count = 1 + static_cast<int>(std::floor(decades * noise.flicker_per_decade + 1e-9));
  for (int k = 0; k < count; ++k) {
    m.corr_time_s.push_back(noise.flicker_min_corr_s *
                            std::pow(10.0, static_cast<double>(k) / noise.flicker_per_decade));
  }
  // IEEE 952: the flicker floor of the ADEV is 0.664 B. Equal variances q^2 per process; q is set
  // so the ADEV of the sum equals the floor at the geometric middle of the band.
  const double floor_dps = units::DphToDps(0.664 * noise.bias_instability_deg_per_h);
  const double tau_mid_s = std::sqrt(m.corr_time_s.front() * m.corr_time_s.back());
  double unit_avar = 0.0;
  for (double T : m.corr_time_s) unit_avar += GaussMarkovAvarUnit(tau_mid_s, T);
  m.process_sigma_dps = floor_dps / std::sqrt(unit_avar);
  return m;
}

double ModelAdevDps(const NoiseOptions& noise, double tau_s) {
  const double n = ArwDpsSqrtS(noise);
  const double k = RrwDpsPerSqrtS(noise);
  const double q = noise.quantization_deg;
  double avar = n * n / tau_s + k * k * tau_s / 3.0 + 3.0 * q * q / (tau_s * tau_s);
  const FlickerModel f = MakeFlickerModel(noise);
  for (double T : f.corr_time_s) {
    avar += f.process_sigma_dps * f.process_sigma_dps * GaussMarkovAvarUnit(tau_s, T);
  }
  return std::sqrt(avar);
}

// ---- the run --------------------------------------------------------------------------------

namespace {

// Number of samples of the run: duration_s * fs_hz rounded, at least 2 and at most 2e8.
Result<std::size_t> SampleCount(const SimulatorOptions& o, double duration_s) {
  const double n_real = std::round(duration_s * o.fs_hz);
  if (n_real < 2.0) {
    return InvalidArgument("SimulatorOptions::duration_s = " + std::to_string(duration_s) +
                           ": fewer than 2 samples at fs_hz = " + std::to_string(o.fs_hz));
  }
  if (n_real > 2.0e8) {
    return InvalidArgument("SimulatorOptions::duration_s * fs_hz = " + std::to_string(n_real) +
                           ": more than 2e8 samples");
  }
  return static_cast<std::size_t>(n_real);
}

// Sensor temperature: first-order thermal lag behind the chamber, and the hysteresis play
// operator that follows it.
class SensorThermal {
 public:
  SensorThermal(const SimulatorOptions& o, double dt, double chamber_start_c)
      : lag_s_(o.thermal_lag_s),
        lag_decay_(lag_s_ > 0.0 ? std::exp(-dt / lag_s_) : 0.0),
        half_width_c_(0.5 * o.bias.hysteresis_width_c),
        u_prev_(chamber_start_c),
        temp_(u_prev_),  // sensor starts in equilibrium with the chamber
        play_(temp_) {}  // hysteresis play operator state

  // Advances to sample i at chamber temperature u (deg C); returns dtemp/dt of the sensor, C/s.
  double Step(std::size_t i, double u, double fs_hz) {
    const double slope_c_per_s = i == 0 ? 0.0 : (u - u_prev_) * fs_hz;
    if (i > 0) {
      // First-order lag, exact for a chamber temperature linear over the step (first-order hold).
      temp_ = lag_s_ > 0.0 ? u - slope_c_per_s * lag_s_ + (temp_ - u_prev_ + slope_c_per_s * lag_s_) * lag_decay_
                           : u;
    }
    u_prev_ = u;
    const double dtemp_c_per_s = lag_s_ > 0.0 ? (u - temp_) / lag_s_ : slope_c_per_s;
    play_ = std::clamp(play_, temp_ - half_width_c_, temp_ + half_width_c_);
    return dtemp_c_per_s;
  }
  double temp_c() const { return temp_; }
  double play_c() const { return play_; }

 private:
  double lag_s_;
  double lag_decay_;
  double half_width_c_;
  double u_prev_;
  double temp_;
  double play_;
};

// Bias drift: polynomial in temperature + temperature-rate term + hysteresis term.
double BiasDriftDps(const BiasModelOptions& bias, double temp_c, double dtemp_c_per_s, double play_c) {
  return Polynomial(bias.poly_dps, temp_c - bias.reference_temp_c) +
         bias.dtemp_coeff_dps_per_c_per_s * dtemp_c_per_s + bias.hysteresis_coeff_dps_per_c * (temp_c - play_c);
}

// IEEE 952 noise terms and the output quantization. Random numbers come from the caller's
// generator, in the order: flicker initial states (construction), then per sample white,
// flicker drives, rate random walk.
class SensorNoise {
 public:
  SensorNoise(const SimulatorOptions& o, double dt, NormalGenerator& gen)
      : fs_hz_(o.fs_hz), dt_(dt), resolution_dps_(o.noise.resolution_dps), flicker_(MakeFlickerModel(o.noise)) {
    const NoiseOptions& nz = o.noise;
    // White rate noise per sample: sigma_ADEV(tau) = N / sqrt(tau) needs sigma = N sqrt(fs).
    white_sigma_dps_ = ArwDpsSqrtS(nz) * std::sqrt(o.fs_hz);
    // Rate random walk increment per sample: K sqrt(dt) gives sigma_ADEV^2 = K^2 tau / 3.
    rrw_step_dps_ = RrwDpsPerSqrtS(nz) * std::sqrt(dt);
    // Angle quantization: rounding the angle to q = sqrt(12) Q gives sigma_ADEV = sqrt(3) Q / tau.
    angle_step_deg_ = std::sqrt(12.0) * nz.quantization_deg;
    // Flicker: exact discretization of each Gauss-Markov process, started in its stationary state.
    const std::size_t nf = flicker_.corr_time_s.size();
    gm_state_.resize(nf);
    gm_phi_.resize(nf);
    gm_drive_.resize(nf);
    for (std::size_t k = 0; k < nf; ++k) {
      gm_phi_[k] = std::exp(-dt / flicker_.corr_time_s[k]);
      gm_drive_[k] = flicker_.process_sigma_dps * std::sqrt(1.0 - gm_phi_[k] * gm_phi_[k]);
      gm_state_[k] = flicker_.process_sigma_dps * gen.Next();
    }
  }

  // White + flicker + rate random walk noise of one sample (deg/s); advances the states.
  double Next(NormalGenerator& gen) {
    double noise = 0.0;
    if (white_sigma_dps_ > 0.0) noise += white_sigma_dps_ * gen.Next();
    for (std::size_t k = 0; k < gm_state_.size(); ++k) {
      noise += gm_state_[k];
      gm_state_[k] = gm_phi_[k] * gm_state_[k] + gm_drive_[k] * gen.Next();
    }
    if (rrw_step_dps_ > 0.0) {
      noise += rrw_dps_;
      rrw_dps_ += rrw_step_dps_ * gen.Next();
    }
    return noise;
  }

  // Angle quantization, then the output resolution, applied to the output rate `out` (deg/s).
  double Quantize(double out) {
    if (angle_step_deg_ > 0.0) {
      angle_deg_ += out * dt_;
      const double angle_q = std::round(angle_deg_ / angle_step_deg_) * angle_step_deg_;
      out = (angle_q - angle_q_prev_) * fs_hz_;
      angle_q_prev_ = angle_q;
    }
    if (resolution_dps_ > 0.0) out = std::round(out / resolution_dps_) * resolution_dps_;
    return out;
  }

  const FlickerModel& flicker() const { return flicker_; }

 private:
  double fs_hz_;
  double dt_;
  double resolution_dps_;
  FlickerModel flicker_;
  double white_sigma_dps_ = 0.0;
  double rrw_step_dps_ = 0.0;
  double angle_step_deg_ = 0.0;
  std::vector<double> gm_state_, gm_phi_, gm_drive_;
  double rrw_dps_ = 0.0;
  double angle_deg_ = 0.0;
  double angle_q_prev_ = 0.0;
};

// Fills the run's summary from its columns.
void Summarize(const SimulatorOptions& o, const FlickerModel& flicker,
               std::chrono::steady_clock::time_point t_start, SimulatedRun* run) {
  const std::size_t n = run->time_s.size();
  SimulationSummary& s = run->summary;
  s.num_samples = n;
  s.duration_s = static_cast<double>(n) / o.fs_hz;
  const auto [tmin, tmax] = std::minmax_element(run->sensor_temp_c.begin(), run->sensor_temp_c.end());
  s.min_temp_c = *tmin;
  s.max_temp_c = *tmax;
  const auto [dmin, dmax] = std::minmax_element(run->true_drift_dps.begin(), run->true_drift_dps.end());
  s.min_drift_dps = *dmin;
  s.max_drift_dps = *dmax;
  s.flicker_process_sigma_dps = flicker.process_sigma_dps;
  s.num_flicker_processes = static_cast<int>(flicker.corr_time_s.size());
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
}

}  // namespace

Result<SimulatedRun> Simulate(const SimulatorOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  const auto t_start = std::chrono::steady_clock::now();
  Result<ThermalSchedule> schedule_or = MakeThermalSchedule(o.profile);
  if (!schedule_or.ok()) return schedule_or.error();
  const ThermalSchedule& schedule = *schedule_or;

  const double duration_s = o.duration_s.value_or(schedule.duration_s());
  const Result<std::size_t> n_or = SampleCount(o, duration_s);
  if (!n_or.ok()) return n_or.error();
  const std::size_t n = *n_or;
  const double dt = 1.0 / o.fs_hz;

  SimulatedRun run;
  run.fs_hz = o.fs_hz;
  for (auto* v : {&run.time_s, &run.rate_dps, &run.temp_c, &run.chamber_temp_c, &run.sensor_temp_c,
                  &run.true_rate_dps, &run.true_drift_dps, &run.true_noise_dps}) {
    v->resize(n);
  }

  NormalGenerator gen(o.seed);
  SensorNoise noise_model(o, dt, gen);  // draws the flicker initial states
  SensorThermal thermal(o, dt, schedule.ChamberTempC(0.0));

  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / o.fs_hz;
    const double u = schedule.ChamberTempC(t);
    const double dtemp_c_per_s = thermal.Step(i, u, o.fs_hz);
    const double temp = thermal.temp_c();
    const double drift = BiasDriftDps(o.bias, temp, dtemp_c_per_s, thermal.play_c());
    const double truth = TrueRateDps(o.true_rate, t);
    const double noise = noise_model.Next(gen);
    const double out = noise_model.Quantize(truth + drift + noise);

    run.time_s[i] = t;
    run.rate_dps[i] = out;
    run.chamber_temp_c[i] = u;
    run.sensor_temp_c[i] = temp;
    run.temp_c[i] = o.temp_noise_c > 0.0 ? temp + o.temp_noise_c * gen.Next() : temp;
    run.true_rate_dps[i] = truth;
    run.true_drift_dps[i] = drift;
    run.true_noise_dps[i] = out - truth - drift;
  }

  Summarize(o, noise_model.flicker(), t_start, &run);
  return run;
}

std::string SimulationSummary::BriefReport() const {
  std::ostringstream os;
  os << "simulated " << num_samples << " samples (" << duration_s / 3600.0 << " h) in " << seconds
     << " s; sensor temperature " << min_temp_c << " .. " << max_temp_c << " C; true drift "
     << min_drift_dps << " .. " << max_drift_dps << " deg/s; flicker: " << num_flicker_processes
     << " Gauss-Markov processes of sigma " << flicker_process_sigma_dps << " deg/s";
  return os.str();
}

namespace {
Table EmptySimulationTable() {
  Table t;
  t.source = "simulate";
  t.names = {"time_s",        "rate_dps",      "temp_c",         "chamber_temp_c",
             "sensor_temp_c", "true_rate_dps", "true_drift_dps", "true_noise_dps"};
  return t;
}
}  // namespace

Table SimulatedRun::ToTable() const& {
  Table t = EmptySimulationTable();
  t.columns = {time_s,        rate_dps,      temp_c,         chamber_temp_c,
               sensor_temp_c, true_rate_dps, true_drift_dps, true_noise_dps};
  return t;
}

Table SimulatedRun::ToTable() && {
  Table t = EmptySimulationTable();
  for (auto* v : {&time_s, &rate_dps, &temp_c, &chamber_temp_c, &sensor_temp_c, &true_rate_dps, &true_drift_dps,
                  &true_noise_dps}) {
    t.columns.push_back(std::move(*v));
  }
  return t;
}

bool AccelAxisOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = "AccelAxisOptions::" + m;
    return false;
  };
  if (bias_poly_m_s2.empty()) return fail("bias_poly_m_s2: needs at least one coefficient");
  for (double v : bias_poly_m_s2)
    if (!std::isfinite(v)) return fail("bias_poly_m_s2: non-finite coefficient");
  if (!(vrw_m_s_per_sqrt_h >= 0.0) || !(bias_instability_m_s2 >= 0.0))
    return fail("vrw_m_s_per_sqrt_h, bias_instability_m_s2: must be >= 0");
  if (!std::isfinite(constant_m_s2) || !std::isfinite(reference_temp_c) || !std::isfinite(dtemp_coeff_m_s2_per_c_per_s))
    return fail("constant_m_s2, reference_temp_c, dtemp_coeff: must be finite");
  return true;
}

Result<AccelAxisRun> SimulateAccelAxis(const SimulatorOptions& chamber, const AccelAxisOptions& a) {
  std::string why;
  if (!a.IsValid(&why)) return InvalidArgument(why);
  // The gyro machinery in the accel's units: "deg/s" read as m/s^2 throughout.
  SimulatorOptions o = chamber;
  o.bias.reference_temp_c = a.reference_temp_c;
  o.bias.poly_dps = a.bias_poly_m_s2;
  o.bias.dtemp_coeff_dps_per_c_per_s = a.dtemp_coeff_m_s2_per_c_per_s;
  o.bias.hysteresis_coeff_dps_per_c = 0.0;
  o.noise = NoiseOptions{};
  o.noise.arw_deg_per_sqrt_h = a.vrw_m_s_per_sqrt_h;         // sigma(1 s) = N / 60 either way
  o.noise.bias_instability_deg_per_h = a.bias_instability_m_s2 * 3600.0;  // B / 3600 per second
  o.noise.rrw_deg_per_h_per_sqrt_h = 0.0;
  o.true_rate = TrueRateOptions{};
  o.true_rate.constant_dps = a.constant_m_s2;
  auto run = Simulate(o);
  if (!run.ok()) return run.error();
  AccelAxisRun out;
  out.time_s = std::move(run->time_s);
  out.accel_m_s2 = std::move(run->rate_dps);
  out.temp_c = std::move(run->temp_c);
  out.true_bias_m_s2 = std::move(run->true_drift_dps);
  return out;
}

bool BoardSimOptions::IsValid(std::string* error) const {
  if (num_imus < 1 || num_imus > 4) {
    if (error) *error = "BoardSimOptions::num_imus = " + std::to_string(num_imus) + ": must be 1..4";
    return false;
  }
  if (!(baro_noise_pa >= 0.0) || !std::isfinite(baro_pressure_pa)) {
    if (error) *error = "BoardSimOptions::baro_noise_pa must be >= 0 and baro_pressure_pa finite";
    return false;
  }
  return chamber.IsValid(error) && accel.IsValid(error);
}

double BoardAxisDriftScale(int imu, int axis) {
  static constexpr double kScale[3] = {1.0, -0.7, 0.5};
  return kScale[axis] * (1.0 + 0.3 * imu);
}

namespace {

std::vector<double> ScaledPoly(std::vector<double> p, double k) {
  for (double& v : p) v *= k;
  return p;
}

Status SimulateBoardImu(const BoardSimOptions& o, int imu, BoardRun* board) {
  const double to_rad = std::numbers::pi / 180.0;
  BoardImuRun r;
  for (int axis = 0; axis < 3; ++axis) {
    SimulatorOptions g = o.chamber;
    g.seed = o.chamber.seed + static_cast<std::uint64_t>(10 * imu + axis);  // IMU 0 x: the chamber run's own seed
    g.bias.poly_dps = ScaledPoly(o.chamber.bias.poly_dps, BoardAxisDriftScale(imu, axis));
    auto gyro = Simulate(g);
    if (!gyro.ok()) return gyro.error();
    if (axis == 0) {
      r.temp_c = gyro->temp_c;
      if (board->time_s.empty()) board->time_s = gyro->time_s, board->fs_hz = gyro->fs_hz;
    }
    for (double& v : gyro->rate_dps) v *= to_rad;
    for (double& v : gyro->true_drift_dps) v *= to_rad;
    r.gyro_rad_s[axis] = std::move(gyro->rate_dps);
    r.true_gyro_drift_rad_s[axis] = std::move(gyro->true_drift_dps);
    AccelAxisOptions a = o.accel;
    a.bias_poly_m_s2 = ScaledPoly(o.accel.bias_poly_m_s2, BoardAxisDriftScale(imu, (axis + 1) % 3));
    a.constant_m_s2 = axis == 2 ? -9.80665 : 0.0;  // board flat, FRD: z reads -g
    SimulatorOptions ac = o.chamber;
    ac.seed = g.seed + 500;
    auto acc = SimulateAccelAxis(ac, a);
    if (!acc.ok()) return acc.error();
    r.accel_m_s2[axis] = std::move(acc->accel_m_s2);
    r.true_accel_bias_m_s2[axis] = std::move(acc->true_bias_m_s2);
  }
  board->imus.push_back(std::move(r));
  return Status::Ok();
}

}  // namespace

Result<BoardRun> SimulateBoard(const BoardSimOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  BoardRun board;
  for (int imu = 0; imu < o.num_imus; ++imu)
    if (Status st = SimulateBoardImu(o, imu, &board); !st.ok()) return st.error();
  if (o.with_baro) {
    // The barometer sits on the board: IMU 0's temperature, its own white noise.
    NormalGenerator noise(o.chamber.seed + 900);
    const std::vector<double>& t = board.imus[0].temp_c;
    board.baro_temp_c = t;
    board.baro_pressure_pa.resize(t.size());
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double d = t[i] - o.chamber.bias.reference_temp_c;
      double p = 0.0;
      for (std::size_t k = o.baro_poly_pa.size(); k-- > 0;) p = p * d + o.baro_poly_pa[k];
      board.baro_pressure_pa[i] = o.baro_pressure_pa + p + o.baro_noise_pa * noise.Next();
    }
  }
  return board;
}

namespace {

// (bus type, bus, address, gyro devtype, accel devtype) of IMUs 0..3 (drv_sensor.h devtypes).
struct BoardChip {
  std::uint32_t bus_type, bus, address, gyro_devtype, accel_devtype;
};
constexpr BoardChip kBoardChips[4] = {{2, 1, 0, 0x3C, 0x3C},   // ICM20689, SPI1
                                      {2, 1, 1, 0x38, 0x38},   // ICM20602, SPI1
                                      {2, 4, 0, 0x42, 0x41},   // BMI055 gyro / accel, SPI4
                                      {2, 4, 1, 0x38, 0x38}};  // ICM20602, SPI4

std::size_t LogStride(const BoardRun& b, double log_rate_hz) {
  if (!(log_rate_hz > 0.0) || log_rate_hz >= b.fs_hz) return 1;
  return static_cast<std::size_t>(std::llround(b.fs_hz / log_rate_hz));
}

Status CheckBoard(const BoardRun& b, double log_rate_hz) {
  if (b.imus.empty() || b.time_s.empty()) return InvalidArgument("board run: no IMU rows");
  if (!(log_rate_hz > 0.0)) return InvalidArgument("log rate must be > 0 Hz");
  return Status::Ok();
}

std::uint64_t Us(double t_s) { return static_cast<std::uint64_t>(std::llround(t_s * 1e6)); }

}  // namespace

std::uint32_t BoardGyroDeviceId(int imu) {
  const BoardChip& c = kBoardChips[imu & 3];
  return Px4DeviceId(c.bus_type, c.bus, c.address, c.gyro_devtype);
}
std::uint32_t BoardAccelDeviceId(int imu) {
  const BoardChip& c = kBoardChips[imu & 3];
  return Px4DeviceId(c.bus_type, c.bus, c.address, c.accel_devtype);
}
std::uint32_t BoardBaroDeviceId() { return Px4DeviceId(2, 4, 2, 0x3D); }  // MS5611, SPI4

Result<std::string> EncodeBoardULog(const BoardRun& b, double log_rate_hz) {
  std::vector<int> order(b.imus.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  return EncodeBoardULogEnumerated(b, log_rate_hz, order);
}

Result<std::string> EncodeBoardULogEnumerated(const BoardRun& b, double log_rate_hz, const std::vector<int>& order) {
  if (Status st = CheckBoard(b, log_rate_hz); !st.ok()) return st.error();
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 0; k < sorted.size(); ++k)
    if (sorted.size() != b.imus.size() || sorted[k] != static_cast<int>(k))
      return InvalidArgument("enumeration order: must be a permutation of the board's " + std::to_string(b.imus.size()) + " IMUs");
  const std::size_t stride = LogStride(b, log_rate_hz);
  ULogWriteInput in;
  in.sys_name = "gyrocomp simulate";
  in.int_parameters = {{"TC_A_ENABLE", 0}, {"TC_B_ENABLE", 0}, {"TC_G_ENABLE", 0}};
  for (std::size_t k = 0; k < b.imus.size(); ++k) {
    const int imu = order[k];  // the IMU the driver enumerated k-th at this boot
    const BoardImuRun& run = b.imus[static_cast<std::size_t>(imu)];
    for (const char* topic : {"sensor_gyro", "sensor_accel"}) {
      const bool gyro = topic[7] == 'g';
      ULogSensorWriteSeries s;
      s.topic = topic;
      s.multi_id = static_cast<int>(k);
      s.device_id = gyro ? BoardGyroDeviceId(imu) : BoardAccelDeviceId(imu);
      const auto& v = gyro ? run.gyro_rad_s : run.accel_m_s2;
      for (std::size_t i = 0; i < b.time_s.size(); i += stride) {
        // Sensors of one board are not sampled at the same microsecond: offset by instance.
        s.timestamp_us.push_back(Us(b.time_s[i]) + 10 * k + (gyro ? 0 : 5));
        s.x.push_back(static_cast<float>(v[0][i]));
        s.y.push_back(static_cast<float>(v[1][i]));
        s.z.push_back(static_cast<float>(v[2][i]));
        s.temperature_c.push_back(static_cast<float>(run.temp_c[i]));
      }
      in.series.push_back(std::move(s));
    }
  }
  if (!b.baro_pressure_pa.empty()) {
    ULogSensorWriteSeries s;
    s.topic = "sensor_baro";
    s.device_id = BoardBaroDeviceId();
    for (std::size_t i = 0; i < b.time_s.size(); i += stride) {
      s.timestamp_us.push_back(Us(b.time_s[i]) + 3);
      s.x.push_back(static_cast<float>(b.baro_pressure_pa[i]));
      s.temperature_c.push_back(static_cast<float>(b.baro_temp_c[i]));
    }
    in.series.push_back(std::move(s));
  }
  return EncodeULog(in);
}

Result<std::string> EncodeBoardDataFlash(const BoardRun& b, double log_rate_hz, int ahrs_orientation) {
  if (Status st = CheckBoard(b, log_rate_hz); !st.ok()) return st.error();
  if (b.imus.size() > 3) return InvalidArgument("DataFlash: ArduPilot logs at most 3 IMUs (INS_TCAL1..3)");
  const auto rot = ArduPilotRotationMatrix(ahrs_orientation);
  if (!rot) return InvalidArgument("AHRS_ORIENTATION " + std::to_string(ahrs_orientation) + ": not a fixed rotation 0..43");
  const std::size_t stride = LogStride(b, log_rate_hz);
  DataFlashWriteInput in;
  in.parameters["AHRS_ORIENTATION"] = static_cast<float>(ahrs_orientation);
  for (std::size_t k = 0; k < b.imus.size(); ++k) {
    in.parameters["INS_TCAL" + std::to_string(k + 1) + "_ENABLE"] = 0.0f;
    DataFlashImuWriteInput m;
    m.instance = static_cast<int>(k);
    m.sample_rate_hz = static_cast<std::uint16_t>(std::min(65535.0, std::round(b.fs_hz)));
    const BoardImuRun& r = b.imus[k];
    for (std::size_t i = 0; i < b.time_s.size(); i += stride) {
      // ArduPilot logs the board frame: R * sensor (Vector3::rotate(AHRS_ORIENTATION)).
      const auto g = RotateVector(*rot, {r.gyro_rad_s[0][i], r.gyro_rad_s[1][i], r.gyro_rad_s[2][i]});
      const auto a = RotateVector(*rot, {r.accel_m_s2[0][i], r.accel_m_s2[1][i], r.accel_m_s2[2][i]});
      m.time_us.push_back(Us(b.time_s[i]));
      m.gyr_x_rad_s.push_back(static_cast<float>(g[0]));
      m.gyr_y_rad_s.push_back(static_cast<float>(g[1]));
      m.gyr_z_rad_s.push_back(static_cast<float>(g[2]));
      m.acc_x_m_s2.push_back(static_cast<float>(a[0]));
      m.acc_y_m_s2.push_back(static_cast<float>(a[1]));
      m.acc_z_m_s2.push_back(static_cast<float>(a[2]));
      m.temp_c.push_back(static_cast<float>(r.temp_c[i]));
    }
    in.imus.push_back(std::move(m));
  }
  return EncodeDataFlash(in);
}

}  // namespace gyrocomp
