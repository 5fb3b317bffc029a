// Unit conversions: the one place they live. Internally rates are deg/s, times s, temperatures
// deg C, frequencies Hz. Datasheet noise units are converted here and nowhere else.
#pragma once

#include <numbers>
#include <optional>
#include <string_view>

namespace gyrocomp {

// Unit of an angular rate in a file or on the command line: deg/s ("dps", the library's internal
// unit), rad/s ("rads"), deg/h ("dph").
enum class RateUnit { kDegPerSec, kRadPerSec, kDegPerHour };

// "dps" | "rads" | "dph" -> RateUnit; nullopt for anything else.
std::optional<RateUnit> ParseRateUnit(std::string_view name);
// RateUnit -> "dps" | "rads" | "dph".
std::string_view RateUnitName(RateUnit unit);

namespace units {

// Seconds in an hour, 3600.
inline constexpr double kSecondsPerHour = 3600.0;
// Degrees per radian, 180 / pi.
inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// Factor that converts a rate in `unit` to deg/s.
constexpr double ToDegPerSec(RateUnit unit) {
  switch (unit) {
    case RateUnit::kDegPerSec: return 1.0;
    case RateUnit::kRadPerSec: return kDegPerRad;
    case RateUnit::kDegPerHour: return 1.0 / kSecondsPerHour;
  }
  return 1.0;
}

// deg/s -> deg/h.
constexpr double DpsToDph(double dps) { return dps * kSecondsPerHour; }
// deg/h -> deg/s.
constexpr double DphToDps(double dph) { return dph / kSecondsPerHour; }

// Angle random walk: sigma(tau = 1 s) in deg/s (= deg/sqrt(s)) <-> deg/sqrt(h).
// 1 deg/sqrt(s) = sqrt(3600) deg/sqrt(h) = 60 deg/sqrt(h). The paper's 1.667 deg/sqrt(h) is
// sigma(1 s) = 0.02778 deg/s = 100 deg/h.
constexpr double DegPerSqrtSecToDegPerSqrtHour(double v) { return v * 60.0; }
// Angle random walk: deg/sqrt(h) -> deg/sqrt(s) (divide by 60).
constexpr double DegPerSqrtHourToDegPerSqrtSec(double v) { return v / 60.0; }

// Rate random walk: deg/s/sqrt(s) <-> deg/h/sqrt(h) (factor 3600 * 60).
constexpr double DpsPerSqrtSecToDphPerSqrtHour(double v) { return v * kSecondsPerHour * 60.0; }
// Rate random walk: deg/h/sqrt(h) -> deg/s/sqrt(s) (divide by 3600 * 60).
constexpr double DphPerSqrtHourToDpsPerSqrtSec(double v) { return v / (kSecondsPerHour * 60.0); }

// Standard gravity, m/s^2 (ISO 80000-3; PX4 CONSTANTS_ONE_G, ArduPilot GRAVITY_MSS).
inline constexpr double kStandardGravity = 9.80665;
// Acceleration: m/s^2 -> mg (thousandths of standard gravity).
constexpr double MetresPerSec2ToMilliG(double a) { return a / (kStandardGravity * 1e-3); }

}  // namespace units
}  // namespace gyrocomp
