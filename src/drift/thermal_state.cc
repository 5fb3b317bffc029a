// Thermal states (see thermal_state.h): causal updates and their batch form.
#include "gyrocomp/drift/thermal_state.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "gyrocomp/core/format.h"

namespace gyrocomp {
namespace {

bool Positive(double v, const char* field, std::string* error) {
  if (std::isfinite(v) && v > 0.0) return true;
  if (error) {
    std::ostringstream s;
    s << "ThermalStateOptions::" << field << " = " << v << ": must be > 0";
    *error = s.str();
  }
  return false;
}

// Discrete first-order lag gain for a step of dt_s: exact for an input held over the step.
double LagGain(double dt_s, double tau_s) { return 1.0 - std::exp(-dt_s / tau_s); }

}  // namespace

std::optional<DriftInputSet> ParseDriftInputSet(std::string_view name) {
  if (name == "temp") return DriftInputSet::kTemp;
  if (name == "temp,dtemp") return DriftInputSet::kTempAndRate;
  if (name == "temp,lag") return DriftInputSet::kTempAndLag;
  if (name == "temp,memory") return DriftInputSet::kTempAndMemory;
  if (name == "temp,dtemp,memory") return DriftInputSet::kTempRateAndMemory;
  return std::nullopt;
}

const char* DriftInputSetName(DriftInputSet inputs) {
  switch (inputs) {
    case DriftInputSet::kTemp: return "temp";
    case DriftInputSet::kTempAndRate: return "temp,dtemp";
    case DriftInputSet::kTempAndLag: return "temp,lag";
    case DriftInputSet::kTempAndMemory: return "temp,memory";
    case DriftInputSet::kTempRateAndMemory: return "temp,dtemp,memory";
  }
  return "?";
}

const char* ThermalStateColumnName(DriftInputSet inputs) {
  switch (inputs) {
    case DriftInputSet::kTemp: return "";
    case DriftInputSet::kTempAndRate:
    case DriftInputSet::kTempRateAndMemory: return "dtemp_c_per_s";
    case DriftInputSet::kTempAndLag: return "lag_excess_c";
    case DriftInputSet::kTempAndMemory: return "memory";
  }
  return "";
}

bool ThermalStateOptions::IsValid(std::string* error) const {
  return Positive(causal_rate_tau_s, "causal_rate_tau_s", error) && Positive(lag_tau_s, "lag_tau_s", error) &&
         Positive(memory_width_c, "memory_width_c", error) &&
         Positive(memory_deadband_c_per_s, "memory_deadband_c_per_s", error);
}

ThermalStateEvaluator::ThermalStateEvaluator(DriftInputSet inputs, const ThermalStateOptions& options)
    : inputs_(inputs), options_(options) {}

double ThermalStateEvaluator::Step(double dt_s, double temp_c) {
  if (!started_) {
    started_ = true;
    l1_ = l2_ = lag_ = temp_c;
    memory_ = 0.0;
    return inputs_ == DriftInputSet::kTempAndMemory ? memory_ : 0.0;  // the rate starts at 0 too
  }
  switch (inputs_) {
    case DriftInputSet::kTemp: return 0.0;
    case DriftInputSet::kTempAndLag: {
      lag_ += LagGain(dt_s, options_.lag_tau_s) * (temp_c - lag_);  // Eq. TS-2
      return temp_c - lag_;
    }
    case DriftInputSet::kTempAndRate:
    case DriftInputSet::kTempAndMemory:
    case DriftInputSet::kTempRateAndMemory: {
      const double tau = options_.causal_rate_tau_s;
      const double a = LagGain(dt_s, tau);
      l1_ += a * (temp_c - l1_);  // Eq. TS-1
      l2_ += a * (l1_ - l2_);
      // Divided by the discrete lags' exact delay of a ramp, d = dt / (exp(dt/tau) - 1)
      // (= tau - dt/2 + O(dt^2)), so a steady ramp gives its slope exactly.
      const double d = dt_s / std::expm1(dt_s / tau);
      const double r = (l1_ - l2_) / d;
      if (inputs_ == DriftInputSet::kTempAndRate) return r;
      if (std::abs(r) > options_.memory_deadband_c_per_s) {  // Eq. TS-3
        const double k = std::min(1.0, std::abs(r) * dt_s / options_.memory_width_c);
        memory_ += k * ((r > 0.0 ? 1.0 : -1.0) - memory_);
      }
      return inputs_ == DriftInputSet::kTempRateAndMemory ? r : memory_;
    }
  }
  return 0.0;
}

namespace {
constexpr double kMinStateTempC = -273.15;  // LogSpec::min_temp_c
constexpr double kMaxStateTempC = 1000.0;   // LogSpec::max_temp_c
}  // namespace

Result<std::vector<double>> ComputeThermalState(std::span<const double> temp_c, double fs_hz,
                                                DriftInputSet inputs, const TemperatureRateOptions& rate,
                                                const ThermalStateOptions& options, bool causal) {
  if (inputs == DriftInputSet::kTemp) return std::vector<double>(temp_c.size(), 0.0);
  // A temperature outside what a log may hold (LogSpec::min_temp_c / max_temp_c, gyro_log.h)
  // makes the lags' differences overflow (fuzz_numeric_drift: +-1.8e308 C gave -inf).
  for (std::size_t i = 0; i < temp_c.size(); ++i) {
    if (!(temp_c[i] >= kMinStateTempC && temp_c[i] <= kMaxStateTempC)) {
      return InvalidInput("thermal state: temperature " + FormatNumber(temp_c[i]) + " C at sample " + std::to_string(i) +
                          ": must be in [-273.15, 1000] C");
    }
  }
  if ((inputs == DriftInputSet::kTempAndRate || inputs == DriftInputSet::kTempRateAndMemory) && !causal)
    return TemperatureRate(temp_c, fs_hz, rate);
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (!(fs_hz > 0.0) || !std::isfinite(fs_hz))
    return InvalidArgument("thermal state: fs_hz must be > 0");
  if (temp_c.size() < 2) return InvalidInput("thermal state: needs at least 2 temperature samples");
  ThermalStateEvaluator ev(inputs, options);
  const double dt_s = 1.0 / fs_hz;
  std::vector<double> s(temp_c.size());
  for (std::size_t i = 0; i < temp_c.size(); ++i) {
    if (!std::isfinite(temp_c[i]))
      return InvalidInput("thermal state: non-finite temperature at sample " + std::to_string(i));
    s[i] = ev.Step(dt_s, temp_c[i]);
  }
  return s;
}

}  // namespace gyrocomp
