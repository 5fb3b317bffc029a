// SimulateFlight (gyrocomp/sim/flight.h).
#include "gyrocomp/sim/flight.h"

#include "gyrocomp/core/units.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gyrocomp/io/ulog.h"
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
  if (!(landed_tilt_deg >= 0.0)) return fail("landed_tilt_deg: must be >= 0");
  return true;
}

namespace {
// sum_k c[k] x^k.
double Cubic(const std::array<double, 4>& c, double x) { return c[0] + x * (c[1] + x * (c[2] + x * c[3])); }
}  // namespace

double FlightGyroDriftRadS(const FlightSimOptions& o, int axis, double temp_c) {
  return o.axis_scale[static_cast<std::size_t>(axis)] * Cubic(o.gyro_drift_dps, temp_c - o.drift_ref_c) * std::numbers::pi / 180.0;
}

double FlightAccelDriftM_S2(const FlightSimOptions& o, int axis, double temp_c) {
  return o.axis_scale[static_cast<std::size_t>(axis)] * Cubic(o.accel_drift_m_s2, temp_c - o.drift_ref_c);
}

Result<FlightRun> SimulateFlight(const FlightSimOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  constexpr double kRad = std::numbers::pi / 180.0, kG = units::kStandardGravity;
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
  // The landing attitude, from its own generator (the noise stream stays that of older versions).
  NormalGenerator tilt_rng(o.seed ^ 0x9e3779b97f4a7c15ULL);
  const double landed_roll = o.landed_tilt_deg * kRad * tilt_rng.Next(), landed_pitch = o.landed_tilt_deg * kRad * tilt_rng.Next();
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
      roll = landed_roll, pitch = landed_pitch;  // landed, slightly tilted
    }
    // Specific force: gravity in the body frame (FRD: -g on z when level) + flight accelerations.
    std::array<double, 3> f = {kG * std::sin(pitch), -kG * std::sin(roll) * std::cos(pitch), -kG * std::cos(roll) * std::cos(pitch)};
    if (flying) for (double& x : f) x += 0.5 * rng.Next();  // gusts and thrust changes
    const double vib_g = armed ? o.vibration_gyro_dps * kRad : 0.0, vib_a = armed ? o.vibration_accel_m_s2 : 0.0;
    r.time_s.push_back(t);
    r.temp_c.push_back(temp);
    for (int a = 0; a < 3; ++a) {
      r.gyro_rad_s[a].push_back(rate[a] + gyro_off[a] + FlightGyroDriftRadS(o, a, temp) + o.gyro_noise_dps * kRad * rng.Next() + vib_g * rng.Next());
      r.accel_m_s2[a].push_back(f[a] + accel_off[a] + FlightAccelDriftM_S2(o, a, temp) + o.accel_noise_m_s2 * rng.Next() + vib_a * rng.Next());
    }
    r.armed.push_back(armed);
    r.landed.push_back(!flying);
    r.truly_still.push_back(!armed);
  }
  return r;
}

namespace {
// The run's armed and landed state as PX4 publishes it: actuator_armed.armed and
// vehicle_status.arming_state (2 armed, 1 disarmed; msg/VehicleStatus.msg) and
// vehicle_land_detected.landed, a row once a second and at every change.
std::vector<ULogStateWriteSeries> FlightStateTopics(const FlightRun& r) {
  std::vector<ULogStateWriteSeries> out(3);
  out[0].topic = "actuator_armed", out[1].topic = "vehicle_status", out[2].topic = "vehicle_land_detected";
  double last_report_s = -1e9;
  for (std::size_t i = 0; i < r.time_s.size(); ++i) {
    const bool change = i > 0 && (r.armed[i] != r.armed[i - 1] || r.landed[i] != r.landed[i - 1]);
    if (!change && r.time_s[i] - last_report_s < 1.0) continue;
    last_report_s = r.time_s[i];
    const auto t_us = static_cast<std::uint64_t>(std::llround(r.time_s[i] * 1e6)) + 1000000;  // as the IMU rows
    for (ULogStateWriteSeries& s : out) s.timestamp_us.push_back(t_us);
    out[0].value.push_back(r.armed[i] ? 1 : 0);
    out[1].value.push_back(r.armed[i] ? 2 : 1);
    out[2].value.push_back(r.landed[i] ? 1 : 0);
  }
  return out;
}
}  // namespace

Result<std::string> EncodeFlightULog(const std::vector<FlightRun>& imus, int decimate, const std::vector<int>& order) {
  if (imus.empty() || decimate < 1) return InvalidArgument("EncodeFlightULog: no IMU, or decimate < 1");
  for (const FlightRun& r : imus)
    if (r.time_s.size() != imus.front().time_s.size()) return InvalidArgument("EncodeFlightULog: IMUs of different lengths");
  std::vector<int> enumerated = order;
  if (enumerated.empty())
    for (std::size_t k = 0; k < imus.size(); ++k) enumerated.push_back(static_cast<int>(k));
  std::vector<int> sorted = enumerated;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 0; k < sorted.size(); ++k)
    if (sorted.size() != imus.size() || sorted[k] != static_cast<int>(k))
      return InvalidArgument("EncodeFlightULog: order must be a permutation of the " + std::to_string(imus.size()) + " IMUs");
  ULogWriteInput in;
  in.int_parameters = {{"TC_G_ENABLE", 0}, {"TC_A_ENABLE", 0}};
  for (std::size_t k = 0; k < imus.size(); ++k) {
    const int imu = enumerated[k];  // the IMU the drivers enumerated k-th at this boot
    const FlightRun& r = imus[static_cast<std::size_t>(imu)];
    ULogSensorWriteSeries g, a;
    g.topic = "sensor_gyro", a.topic = "sensor_accel";
    g.multi_id = a.multi_id = static_cast<int>(k);
    g.device_id = BoardGyroDeviceId(imu), a.device_id = BoardAccelDeviceId(imu);
    for (std::size_t i = 0; i < r.time_s.size(); i += static_cast<std::size_t>(decimate)) {
      const auto t_us = static_cast<std::uint64_t>(std::llround(r.time_s[i] * 1e6)) + 1000000;  // logging starts at 1 s
      for (ULogSensorWriteSeries* s : {&g, &a}) s->timestamp_us.push_back(t_us), s->temperature_c.push_back(static_cast<float>(r.temp_c[i]));
      g.x.push_back(static_cast<float>(r.gyro_rad_s[0][i])), g.y.push_back(static_cast<float>(r.gyro_rad_s[1][i]));
      g.z.push_back(static_cast<float>(r.gyro_rad_s[2][i]));
      a.x.push_back(static_cast<float>(r.accel_m_s2[0][i])), a.y.push_back(static_cast<float>(r.accel_m_s2[1][i]));
      a.z.push_back(static_cast<float>(r.accel_m_s2[2][i]));
    }
    in.series.push_back(std::move(g));
    in.series.push_back(std::move(a));
  }
  in.states = FlightStateTopics(imus.front());
  return EncodeULog(in);
}

}  // namespace gyrocomp
