// Robust dT/dt: least-squares slope over a centred window (see temperature_rate.h).
#include "gyrocomp/drift/temperature_rate.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace gyrocomp {

bool TemperatureRateOptions::IsValid(std::string* error) const {
  if (!(window_s > 0.0) || !std::isfinite(window_s)) {
    if (error) {
      std::ostringstream s;
      s << "TemperatureRateOptions::window_s = " << window_s << ": must be > 0";
      *error = s.str();
    }
    return false;
  }
  return true;
}

Result<std::vector<double>> TemperatureRate(std::span<const double> temp_c, double fs_hz,
                                            const TemperatureRateOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (!(fs_hz > 0.0) || !std::isfinite(fs_hz))
    return InvalidArgument("TemperatureRate: fs_hz must be > 0");
  const std::size_t n = temp_c.size();
  if (n < 2) return InvalidInput("TemperatureRate: need at least 2 temperature samples");
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(temp_c[i]))
      return InvalidInput("TemperatureRate: non-finite temperature at sample " + std::to_string(i));

  // Half-width in samples: the window spans 2h + 1 samples ~ window_s seconds, at least 1.
  const double half = std::floor(options.window_s * fs_hz / 2.0);
  const std::size_t h = static_cast<std::size_t>(std::clamp(half, 1.0, static_cast<double>(n)));

  // Running sums of T and i*T relative to T[0] (conditioning), over [a, b]:
  //   slope (per sample) = sum (i - ibar)(T_i - T0) / sum (i - ibar)^2,
  // a first-order Savitzky-Golay differentiator; the window is truncated at the ends.
  // The numerator is a difference of prefix sums that grow like n^3 while it grows like W^3:
  // its relative rounding error is about 4 eps (n / W)^3, 2e-12 for n = 20000, W = 1500 in
  // double. Long double (64-bit mantissa on x86) makes that ~1e-15, and ~2e-12 for 5e6 samples.
  const double t0 = temp_c[0];
  std::vector<long double> s_t(n + 1, 0.0L), s_it(n + 1, 0.0L);
  for (std::size_t i = 0; i < n; ++i) {
    const long double v = static_cast<long double>(temp_c[i]) - t0;
    s_t[i + 1] = s_t[i] + v;
    s_it[i + 1] = s_it[i] + static_cast<long double>(i) * v;
  }
  std::vector<double> rate(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = i >= h ? i - h : 0;
    const std::size_t b = std::min(n - 1, i + h);
    const long double m = static_cast<long double>(b - a + 1);
    const long double ibar = (static_cast<long double>(a) + static_cast<long double>(b)) / 2.0L;
    // sum (i - ibar)^2 over consecutive integers = m (m^2 - 1) / 12.
    const long double sxx = m * (m * m - 1.0L) / 12.0L;
    const long double st = s_t[b + 1] - s_t[a];
    const long double sit = s_it[b + 1] - s_it[a];
    const long double sxy = sit - ibar * st;
    rate[i] = static_cast<double>(sxy / sxx) * fs_hz;  // deg C per sample -> deg C per second
  }
  return rate;
}

}  // namespace gyrocomp
