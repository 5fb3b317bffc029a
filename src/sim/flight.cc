// SimulateFlight (gyrocomp/sim/flight.h).
#include "gyrocomp/sim/flight.h"

#include <cmath>
#include <numbers>

#include "gyrocomp/sim/simulator.h"

namespace gyrocomp {

bool FlightSimOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = std::string("FlightSimOptions::") + m;
    return false;
  };
  if (!(fs_hz > 0.0)) return fail("fs_hz: must be > 0");
  if (!(still_before_s >= 0.0 && armed_ground_s >= 0.0 && flight_s >= 0.0 && landed_armed_s >= 0.0 && still_after_s >= 0.0))
    return fail("phase durations: must be >= 0 s");
  if (!(self_heating_tau_s > 0.0)) return fail("self_heating_tau_s: must be > 0");
  return true;
}

Result<FlightRun> SimulateFlight(const FlightSimOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  constexpr double kRad = std::numbers::pi / 180.0, kG = 9.80665;
  NormalGenerator rng(o.seed);
  std::array<double, 3> gyro_off{}, accel_off{};
  for (int a = 0; a < 3; ++a) gyro_off[a] = o.gyro_offset_dps * kRad * rng.Next(), accel_off[a] = o.accel_offset_m_s2 * rng.Next();
  // Manoeuvre phases and frequencies of this flight.
  std::array<double, 3> f_hz{}, ph{};
  for (int a = 0; a < 3; ++a) f_hz[a] = 0.05 + 0.25 * rng.Uniform(), ph[a] = 2.0 * std::numbers::pi * rng.Uniform();
  const double t_arm = o.still_before_s, t_up = t_arm + o.armed_ground_s, t_down = t_up + o.flight_s;
  const double t_disarm = t_down + o.landed_armed_s, t_end = t_disarm + o.still_after_s;
  const auto n = static_cast<std::size_t>(std::floor(t_end * o.fs_hz));
  FlightRun r;
  double temp = o.ambient_c, roll = 0.0, pitch = 0.0;
  const double dt = 1.0 / o.fs_hz;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * dt;
    const bool armed = t >= t_arm && t < t_disarm, flying = t >= t_up && t < t_down;
    // Board temperature: first-order towards ambient + self-heating (- airflow cooling in flight).
    const double target = o.ambient_c + o.self_heating_c - (flying ? o.airflow_cooling_c : 0.0);
    temp += (target - temp) * dt / o.self_heating_tau_s * (flying ? 3.0 : 1.0);
    std::array<double, 3> rate{};  // body rates, rad/s
    if (flying) {
      // Manoeuvres: roll and pitch follow bounded sinusoids (+-25 deg), yaw rate a sinusoid.
      const double amp = o.manoeuvre_rate_dps * kRad;
      const double new_roll = 0.44 * std::sin(2.0 * std::numbers::pi * f_hz[0] * (t - t_up) + ph[0]) * std::min(1.0, (t - t_up) / 5.0);
      const double new_pitch = 0.44 * std::sin(2.0 * std::numbers::pi * f_hz[1] * (t - t_up) + ph[1]) * std::min(1.0, (t - t_up) / 5.0);
      rate[0] = (new_roll - roll) / dt, rate[1] = (new_pitch - pitch) / dt;
      rate[2] = amp * std::sin(2.0 * std::numbers::pi * f_hz[2] * (t - t_up) + ph[2]);
      roll = new_roll, pitch = new_pitch;
    } else if (t >= t_down) {
      roll = pitch = 0.0;  // landed level
    }
    // Specific force: gravity in the body frame (FRD: -g on z when level) + flight accelerations.
    std::array<double, 3> f = {kG * std::sin(pitch), -kG * std::sin(roll) * std::cos(pitch), -kG * std::cos(roll) * std::cos(pitch)};
    if (flying) for (double& x : f) x += 0.5 * rng.Next();  // gusts and thrust changes
    const double vib_g = armed ? o.vibration_gyro_dps * kRad : 0.0, vib_a = armed ? o.vibration_accel_m_s2 : 0.0;
    r.time_s.push_back(t);
    r.temp_c.push_back(temp);
    for (int a = 0; a < 3; ++a) {
      r.gyro_rad_s[a].push_back(rate[a] + gyro_off[a] + o.gyro_noise_dps * kRad * rng.Next() + vib_g * rng.Next());
      r.accel_m_s2[a].push_back(f[a] + accel_off[a] + o.accel_noise_m_s2 * rng.Next() + vib_a * rng.Next());
    }
    r.armed.push_back(armed);
    r.landed.push_back(!flying);
    r.truly_still.push_back(!armed);
  }
  return r;
}

}  // namespace gyrocomp
