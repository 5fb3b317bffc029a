// What the denoisers (FLP, WFLP, wavelet denoising) accept, and the power-of-two normalisation
// of records near the ends of the double range (found by fuzz_numeric_stages:
// +-1.8e308 alternating gave NaN / -inf with a success status). Internal to src/denoise/.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"

namespace gyrocomp::denoise_internal {

// The input checks of every denoiser, named by `denoiser` ("FLP: empty signal", "FLP: sample 7
// is not finite"); nullopt when x can be denoised.
inline std::optional<Error> SignalError(std::span<const double> x, const std::string& denoiser) {
  if (x.empty()) return InvalidInput(denoiser + ": empty signal");
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i])) return InvalidInput(denoiser + ": sample " + std::to_string(i) + " is not finite");
  }
  return std::nullopt;
}

// A power of two that brings max |x| into [1, 2) when it is beyond 2^+-500, else 1. Multiplying
// by a power of two is exact, so records of ordinary magnitude are not touched at all and the
// linear steps (DWT, MAD, thresholds) of an extreme one give the same bits scaled.
inline double NormalisingScale(std::span<const double> x) {
  double top = 0.0;
  for (double v : x) top = std::max(top, std::abs(v));
  if (top == 0.0 || (top < 0x1p500 && top > 0x1p-500)) return 1.0;
  return std::ldexp(1.0, -std::ilogb(top));
}

inline std::vector<double> Scaled(std::span<const double> x, double scale) {
  std::vector<double> out(x.begin(), x.end());
  for (double& v : out) v *= scale;
  return out;
}

// Divides `y` by `scale` in place; false when a value leaves the double range.
inline bool Unscale(std::vector<double>* y, double scale) {
  for (double& v : *y) {
    v /= scale;
    if (!std::isfinite(v)) return false;
  }
  return true;
}

}  // namespace gyrocomp::denoise_internal
