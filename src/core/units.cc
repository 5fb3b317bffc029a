#include "gyrocomp/core/units.h"

namespace gyrocomp {

std::optional<RateUnit> ParseRateUnit(std::string_view name) {
  if (name == "dps") return RateUnit::kDegPerSec;
  if (name == "rads") return RateUnit::kRadPerSec;
  if (name == "dph") return RateUnit::kDegPerHour;
  return std::nullopt;
}

std::string_view RateUnitName(RateUnit unit) {
  switch (unit) {
    case RateUnit::kDegPerSec: return "dps";
    case RateUnit::kRadPerSec: return "rads";
    case RateUnit::kDegPerHour: return "dph";
  }
  return "dps";
}

}  // namespace gyrocomp
