#include "console.h"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <numbers>

#include <unistd.h>

#include "gyrocomp/core/format.h"

namespace gyrocomp::cli {

bool UseColour() {
  const char* no_colour = std::getenv("NO_COLOR");
  if (no_colour != nullptr && no_colour[0] != '\0') return false;
  return isatty(STDERR_FILENO) != 0;
}

std::string Bold(const std::string& text) { return UseColour() ? "\033[1m" + text + "\033[0m" : text; }

std::string WarnColour(const std::string& text) { return UseColour() ? "\033[33m" + text + "\033[0m" : text; }

std::string Figure(double v, int digits) {
  if (!std::isfinite(v)) return "n/a";
  if (std::abs(v) < 1e-7) return "0";
  return FormatNumber(v, digits);
}

std::string Figure(const std::optional<double>& v, int digits) { return v ? Figure(*v, digits) : "n/a"; }

std::string RateDps(double dps, int digits) {
  if (!std::isfinite(dps)) return "n/a";
  if (std::abs(dps) >= 1.0) return Figure(dps, digits) + " deg/s";
  return Figure(dps * 1e3, digits) + " mdps";
}

std::string RateRadS(double rad_s, int digits) { return RateDps(rad_s * 180.0 / std::numbers::pi, digits); }

std::string BeforeAfter(double before, double after, const std::string& unit, int digits) {
  std::string s = Figure(before, digits) + " -> " + Figure(after, digits) + " " + unit;
  if (std::isfinite(before) && std::isfinite(after) && before > 0.0 && after >= 0.0) {
    s += " (" + Figure(after / before, 2) + "x)";
  }
  return s;
}

void Headline(const std::string& command, const std::string& text) {
  std::cerr << Bold("gyrocomp " + command + ":") << " " << text << "\n";
}

void Line(const std::string& text) { std::cerr << "  " << text << "\n"; }

void Wrote(const std::vector<std::string>& paths) {
  std::string list;
  for (const std::string& p : paths) {
    if (p.empty() || p == "-") continue;
    list += (list.empty() ? "" : ", ") + p;
  }
  if (!list.empty()) Line("wrote " + list);
}

}  // namespace gyrocomp::cli
