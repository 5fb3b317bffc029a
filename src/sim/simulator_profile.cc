// Thermal-chamber schedules and option validation for the simulator (paper Section 4.1).
#include <algorithm>
#include <cassert>
#include <cmath>
#include <sstream>
#include <string>

#include "gyrocomp/sim/simulator.h"

namespace gyrocomp {
namespace {

// Formats "Struct::field = value: must be ..." (style.md) into *error; returns false.
bool Fail(std::string* error, const char* field, double value, const char* rule) {
  if (error != nullptr) {
    std::ostringstream os;
    os << field << " = " << value << ": " << rule;
    *error = os.str();
  }
  return false;
}

bool Finite(double v) { return std::isfinite(v); }

// Builds a piecewise-linear schedule: holds and ramps at a fixed slew rate.
class ScheduleBuilder {
 public:
  ScheduleBuilder(double start_c, double ramp_rate_c_per_s) : rate_(ramp_rate_c_per_s) {
    s_.time_s.push_back(0.0);
    s_.temp_c.push_back(start_c);
  }
  void Hold(double seconds) {
    if (seconds <= 0.0) return;
    s_.time_s.push_back(s_.time_s.back() + seconds);
    s_.temp_c.push_back(s_.temp_c.back());
  }
  void RampTo(double temp_c) { RampTo(temp_c, rate_); }
  void RampTo(double temp_c, double rate_c_per_s) {
    const double delta = std::abs(temp_c - s_.temp_c.back());
    if (delta == 0.0) return;
    s_.time_s.push_back(s_.time_s.back() + delta / rate_c_per_s);
    s_.temp_c.push_back(temp_c);
  }
  ThermalSchedule Take() {
    if (s_.time_s.size() == 1) Hold(1.0);  // a schedule always spans a positive duration
    return std::move(s_);
  }

 private:
  ThermalSchedule s_;
  double rate_;
};

// kUser: sizes, finite values, strictly increasing times from >= 0, plausible temperatures.
bool UserScheduleValid(const std::vector<double>& time_s, const std::vector<double>& temp_c, std::string* error) {
  if (time_s.size() != temp_c.size() || time_s.size() < 2)
    return Fail(error, "ThermalProfileOptions::user_time_s.size()", static_cast<double>(time_s.size()),
                "must equal user_temp_c.size() and be >= 2");
  for (std::size_t i = 0; i < time_s.size(); ++i) {
    if (!Finite(time_s[i]) || time_s[i] < 0.0 || (i > 0 && !(time_s[i] > time_s[i - 1])))
      return Fail(error, "ThermalProfileOptions::user_time_s[i]", time_s[i], "must be finite, >= 0 and increasing");
    if (!Finite(temp_c[i]) || temp_c[i] < -273.15 || temp_c[i] > 1000.0)
      return Fail(error, "ThermalProfileOptions::user_temp_c[i]", temp_c[i], "must be a temperature in [-273.15, 1000] deg C");
  }
  return true;
}

}  // namespace

std::optional<ThermalProfileKind> ParseThermalProfileKind(const std::string& name) {
  if (name == "paper") return ThermalProfileKind::kPaper;
  if (name == "soak") return ThermalProfileKind::kSoak;
  if (name == "ramp") return ThermalProfileKind::kRamp;
  if (name == "cycle") return ThermalProfileKind::kCycle;
  if (name == "heat-cool") return ThermalProfileKind::kHeatCool;
  if (name == "stairs") return ThermalProfileKind::kStairs;
  if (name == "rate-cycles") return ThermalProfileKind::kRateCycles;
  if (name == "user") return ThermalProfileKind::kUser;
  return std::nullopt;
}

const char* ThermalProfileKindName(ThermalProfileKind kind) {
  switch (kind) {
    case ThermalProfileKind::kPaper: return "paper";
    case ThermalProfileKind::kSoak: return "soak";
    case ThermalProfileKind::kRamp: return "ramp";
    case ThermalProfileKind::kCycle: return "cycle";
    case ThermalProfileKind::kHeatCool: return "heat-cool";
    case ThermalProfileKind::kStairs: return "stairs";
    case ThermalProfileKind::kRateCycles: return "rate-cycles";
    case ThermalProfileKind::kUser: return "user";
  }
  return "?";
}

bool ThermalProfileOptions::IsValid(std::string* error) const {
  const struct { const char* name; double v; } temps[] = {
      {"ThermalProfileOptions::room_temp_c", room_temp_c},
      {"ThermalProfileOptions::hot_temp_c", hot_temp_c},
      {"ThermalProfileOptions::cold_temp_c", cold_temp_c},
      {"ThermalProfileOptions::soak_temp_c", soak_temp_c},
      {"ThermalProfileOptions::ramp_end_c", ramp_end_c}};
  for (const auto& t : temps) {
    if (!Finite(t.v) || t.v < -273.15 || t.v > 1000.0) {
      return Fail(error, t.name, t.v, "must be a temperature in [-273.15, 1000] deg C");
    }
  }
  if (!(hot_temp_c > cold_temp_c)) {
    return Fail(error, "ThermalProfileOptions::hot_temp_c", hot_temp_c, "must be > cold_temp_c");
  }
  if (!Finite(step_c) || step_c <= 0.0) return Fail(error, "ThermalProfileOptions::step_c", step_c, "must be > 0");
  if (!Finite(room_hold_s) || room_hold_s < 0.0) {
    return Fail(error, "ThermalProfileOptions::room_hold_s", room_hold_s, "must be >= 0");
  }
  if (!Finite(hold_s) || hold_s < 0.0) return Fail(error, "ThermalProfileOptions::hold_s", hold_s, "must be >= 0");
  if (!Finite(ramp_rate_c_per_min) || ramp_rate_c_per_min <= 0.0) {
    return Fail(error, "ThermalProfileOptions::ramp_rate_c_per_min", ramp_rate_c_per_min, "must be > 0");
  }
  if (!Finite(soak_duration_s) || soak_duration_s <= 0.0) {
    return Fail(error, "ThermalProfileOptions::soak_duration_s", soak_duration_s, "must be > 0");
  }
  if (num_cycles < 1 || num_cycles > 1000) {
    return Fail(error, "ThermalProfileOptions::num_cycles", num_cycles, "must be in [1, 1000]");
  }
  if (kind == ThermalProfileKind::kUser) return UserScheduleValid(user_time_s, user_temp_c, error);
  return true;
}

Result<ThermalSchedule> MakeThermalSchedule(const ThermalProfileOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  const double rate_c_per_s = o.ramp_rate_c_per_min / 60.0;
  switch (o.kind) {
    case ThermalProfileKind::kPaper: {
      // Section 4.1: 1 h at room temperature, heat to 60 C, hold 1 h, then every 10 C down to
      // -40 C held 1 h (the last step is shortened to land exactly on cold_temp_c).
      ScheduleBuilder b(o.room_temp_c, rate_c_per_s);
      b.Hold(o.room_hold_s);
      b.RampTo(o.hot_temp_c);
      b.Hold(o.hold_s);
      double t = o.hot_temp_c;
      while (t > o.cold_temp_c + 1e-9) {
        t = std::max(o.cold_temp_c, t - o.step_c);
        b.RampTo(t);
        b.Hold(o.hold_s);
      }
      return b.Take();
    }
    case ThermalProfileKind::kSoak: {
      ScheduleBuilder b(o.soak_temp_c, rate_c_per_s);
      b.Hold(o.soak_duration_s);
      return b.Take();
    }
    case ThermalProfileKind::kRamp: {
      ScheduleBuilder b(o.room_temp_c, rate_c_per_s);
      b.Hold(o.room_hold_s);
      b.RampTo(o.ramp_end_c);
      b.Hold(o.hold_s);
      return b.Take();
    }
    case ThermalProfileKind::kCycle: {
      // Heating and cooling over the same range, to expose hysteresis.
      ScheduleBuilder b(o.room_temp_c, rate_c_per_s);
      b.Hold(o.room_hold_s);
      for (int c = 0; c < o.num_cycles; ++c) {
        b.RampTo(o.hot_temp_c);
        b.Hold(o.hold_s);
        b.RampTo(o.cold_temp_c);
        b.Hold(o.hold_s);
        b.RampTo(o.room_temp_c);
        b.Hold(o.hold_s);
      }
      return b.Take();
    }
    case ThermalProfileKind::kHeatCool: {
      // Both directions over the whole range, holds at both ends (a cold soak first,
      // as PX4's procedure starts), so a memory and a lag are identifiable (Eqs. I-2, I-3).
      ScheduleBuilder b(o.cold_temp_c, rate_c_per_s);
      b.Hold(o.room_hold_s);
      b.RampTo(o.hot_temp_c);
      b.Hold(o.hold_s);
      b.RampTo(o.cold_temp_c);
      b.Hold(o.hold_s);
      return b.Take();
    }
    case ThermalProfileKind::kStairs: {
      // A staircase up and one down, so that at every temperature the run holds and
      // ramps (Eq. I-1: the dT/dt gain) in both directions (Eq. I-3: the memory). Heating: steps
      // of 2 step_c from cold to hot at ramp_rate; cooling: steps of 2 step_c offset by step_c
      // (plateaus between the heating ones) at ramp_rate / 2; every plateau held hold_s / 2.
      // Two ramp rates and holds in both directions separate the gain (drift ~ dT/dt: zero on
      // every hold, doubled on the fast ramps) from the memory (drift ~ the last direction:
      // unchanged over a hold), which heat-cool's equal ramps and end holds do not.
      ScheduleBuilder b(o.cold_temp_c, rate_c_per_s);
      const double step = 2.0 * o.step_c, plateau_s = 0.5 * o.hold_s;
      b.Hold(o.room_hold_s);
      for (double t = o.cold_temp_c; t < o.hot_temp_c - 1e-9;) {
        t = std::min(o.hot_temp_c, t + step);
        b.RampTo(t);
        b.Hold(plateau_s);
      }
      for (double t = o.hot_temp_c - o.step_c; o.hot_temp_c - o.cold_temp_c > o.step_c;) {
        b.RampTo(std::max(o.cold_temp_c, t), 0.5 * rate_c_per_s);
        b.Hold(plateau_s);
        if (t <= o.cold_temp_c + 1e-9) break;
        t -= step;
      }
      return b.Take();
    }
    case ThermalProfileKind::kRateCycles: {
      // docs/explanation/calibration-design.md "What any estimator can reach": the calibration run's slow
      // (flicker, random-walk) noise is what limits the next run's error; every reversal of the
      // temperature decorrelates the drift's shape from it, so four full-range cycles in the time
      // of the paper's one sweep leave the least of it (bench/drift_design_bound.py: 0.56-0.95x of
      // poly(T, dT/dt) on the paper run for OLS of the true form, stairs 0.68-1.04x).
      // Two rates each way (fast up / slow down, then the reverse) separate a dT/dt gain from a
      // heating/cooling memory, as stairs does (Eq. I-1).
      ScheduleBuilder b(o.cold_temp_c, rate_c_per_s);
      b.Hold(0.5 * o.room_hold_s);
      for (int c = 0; c < 4; ++c) {
        const double up = c % 2 == 0 ? 2.0 : 1.0, down = c % 2 == 0 ? 1.0 : 2.0;
        b.RampTo(o.hot_temp_c, up * rate_c_per_s);
        b.Hold(o.hold_s / 3.0);
        b.RampTo(o.cold_temp_c, down * rate_c_per_s);
        b.Hold(o.hold_s / 3.0);
      }
      return b.Take();
    }
    case ThermalProfileKind::kUser: {
      ThermalSchedule s;
      if (o.user_time_s.front() > 0.0) {  // held at the first temperature from t = 0
        s.time_s.push_back(0.0);
        s.temp_c.push_back(o.user_temp_c.front());
      }
      s.time_s.insert(s.time_s.end(), o.user_time_s.begin(), o.user_time_s.end());
      s.temp_c.insert(s.temp_c.end(), o.user_temp_c.begin(), o.user_temp_c.end());
      return s;
    }
  }
  return InternalError("MakeThermalSchedule: unknown profile kind");
}

double ThermalSchedule::ChamberTempC(double t_s) const {
  assert(!time_s.empty());
  if (t_s <= time_s.front()) return temp_c.front();
  if (t_s >= time_s.back()) return temp_c.back();
  const auto it = std::upper_bound(time_s.begin(), time_s.end(), t_s);
  const std::size_t j = static_cast<std::size_t>(it - time_s.begin());  // time_s[j-1] <= t < time_s[j]
  const double f = (t_s - time_s[j - 1]) / (time_s[j] - time_s[j - 1]);
  return temp_c[j - 1] + f * (temp_c[j] - temp_c[j - 1]);
}

bool BiasModelOptions::IsValid(std::string* error) const {
  if (!Finite(reference_temp_c)) {
    return Fail(error, "BiasModelOptions::reference_temp_c", reference_temp_c, "must be finite");
  }
  if (poly_dps.size() > 8) {
    return Fail(error, "BiasModelOptions::poly_dps.size()", static_cast<double>(poly_dps.size()),
                "must be <= 8 (degree <= 7)");
  }
  for (double c : poly_dps) {
    if (!Finite(c)) return Fail(error, "BiasModelOptions::poly_dps[k]", c, "must be finite");
  }
  if (!Finite(dtemp_coeff_dps_per_c_per_s)) {
    return Fail(error, "BiasModelOptions::dtemp_coeff_dps_per_c_per_s", dtemp_coeff_dps_per_c_per_s,
                "must be finite");
  }
  if (!Finite(hysteresis_width_c) || hysteresis_width_c < 0.0) {
    return Fail(error, "BiasModelOptions::hysteresis_width_c", hysteresis_width_c, "must be >= 0");
  }
  if (!Finite(hysteresis_coeff_dps_per_c)) {
    return Fail(error, "BiasModelOptions::hysteresis_coeff_dps_per_c", hysteresis_coeff_dps_per_c,
                "must be finite");
  }
  return true;
}

bool NoiseOptions::IsValid(std::string* error) const {
  const struct { const char* name; double v; } nonneg[] = {
      {"NoiseOptions::arw_deg_per_sqrt_h", arw_deg_per_sqrt_h},
      {"NoiseOptions::bias_instability_deg_per_h", bias_instability_deg_per_h},
      {"NoiseOptions::rrw_deg_per_h_per_sqrt_h", rrw_deg_per_h_per_sqrt_h},
      {"NoiseOptions::quantization_deg", quantization_deg},
      {"NoiseOptions::resolution_dps", resolution_dps}};
  for (const auto& t : nonneg) {
    if (!Finite(t.v) || t.v < 0.0) return Fail(error, t.name, t.v, "must be >= 0 (0 = off)");
  }
  if (bias_instability_deg_per_h > 0.0) {
    if (!Finite(flicker_min_corr_s) || flicker_min_corr_s <= 0.0) {
      return Fail(error, "NoiseOptions::flicker_min_corr_s", flicker_min_corr_s, "must be > 0");
    }
    if (!Finite(flicker_max_corr_s) || flicker_max_corr_s < flicker_min_corr_s) {
      return Fail(error, "NoiseOptions::flicker_max_corr_s", flicker_max_corr_s,
                  "must be >= flicker_min_corr_s");
    }
    if (flicker_per_decade < 1 || flicker_per_decade > 20) {
      return Fail(error, "NoiseOptions::flicker_per_decade", flicker_per_decade, "must be in [1, 20]");
    }
  }
  return true;
}

bool TrueRateOptions::IsValid(std::string* error) const {
  if (!Finite(constant_dps)) return Fail(error, "TrueRateOptions::constant_dps", constant_dps, "must be finite");
  if (!Finite(step_amplitude_dps)) {
    return Fail(error, "TrueRateOptions::step_amplitude_dps", step_amplitude_dps, "must be finite");
  }
  if (step_amplitude_dps != 0.0 && (!Finite(step_period_s) || step_period_s <= 0.0)) {
    return Fail(error, "TrueRateOptions::step_period_s", step_period_s, "must be > 0");
  }
  if (!Finite(sine_amplitude_dps)) {
    return Fail(error, "TrueRateOptions::sine_amplitude_dps", sine_amplitude_dps, "must be finite");
  }
  if (sine_amplitude_dps != 0.0 && (!Finite(sine_frequency_hz) || sine_frequency_hz <= 0.0)) {
    return Fail(error, "TrueRateOptions::sine_frequency_hz", sine_frequency_hz, "must be > 0");
  }
  return true;
}

bool SimulatorOptions::IsValid(std::string* error) const {
  if (!Finite(fs_hz) || fs_hz <= 0.0 || fs_hz > 1.0e6) {
    return Fail(error, "SimulatorOptions::fs_hz", fs_hz, "must be in (0, 1e6] Hz");
  }
  if (duration_s && (!Finite(*duration_s) || *duration_s <= 0.0)) {
    return Fail(error, "SimulatorOptions::duration_s", *duration_s, "must be > 0");
  }
  if (!Finite(thermal_lag_s) || thermal_lag_s < 0.0) {
    return Fail(error, "SimulatorOptions::thermal_lag_s", thermal_lag_s, "must be >= 0");
  }
  if (!Finite(temp_noise_c) || temp_noise_c < 0.0) {
    return Fail(error, "SimulatorOptions::temp_noise_c", temp_noise_c, "must be >= 0");
  }
  return profile.IsValid(error) && bias.IsValid(error) && noise.IsValid(error) &&
         true_rate.IsValid(error);
}

}  // namespace gyrocomp
