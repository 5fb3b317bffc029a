// Shared check of the denoisers near the ends of the double range (found by fuzz_numeric_stages:
// +-1.8e308 alternating gave NaN / -inf with a success status). Records beyond 2^+-500 are
// denoised as a power-of-two scaled copy: the same bits scaled, or a refusal with a message when
// the result itself leaves the double range. Used by the wavelet, FLP and WFLP tests.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

namespace gyrocomp::testing {

// `denoise(x)` returns Result<std::vector<double>>.
template <class Denoise>
void ExpectDenoiseScaleFreeNearTheEndsOfTheDoubleRange(Denoise denoise) {
  std::vector<double> x(64);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = (i % 2 ? 1.0 : -1.0) * std::numeric_limits<double>::max();
  const auto r = denoise(x);
  if (r.ok()) {
    for (double v : *r) EXPECT_TRUE(std::isfinite(v));
  } else {
    EXPECT_FALSE(r.error().message.empty());
  }
  std::vector<double> y(300), big(300), tiny(300);
  for (std::size_t i = 0; i < y.size(); ++i) {
    y[i] = std::sin(0.05 * static_cast<double>(i)) + 0.1 * ((static_cast<int>(i * 7919 % 101)) - 50) / 50.0;
    big[i] = std::ldexp(y[i], 900);
    tiny[i] = std::ldexp(y[i], -900);
  }
  const auto a = denoise(y);
  const auto b = denoise(big);
  const auto c = denoise(tiny);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  for (std::size_t i = 0; i < y.size(); ++i) {
    EXPECT_EQ(std::ldexp((*a)[i], 900), (*b)[i]) << i;
    EXPECT_EQ(std::ldexp((*a)[i], -900), (*c)[i]) << i;
  }
}

}  // namespace gyrocomp::testing
