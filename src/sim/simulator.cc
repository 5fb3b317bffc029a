// The chamber-experiment simulator: sensor thermal lag, temperature-dependent bias with rate and
// hysteresis terms, IEEE 952 noise terms. Model and units: docs/simulator.md.
#include "gyrocomp/sim/simulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <utility>

#include "gyrocomp/core/units.h"

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

}  // namespace gyrocomp
