// Turns fuzzer bytes into a series of finite doubles with the shapes that break numerical code:
// subnormals, 1e-308..1e308, constants, alternating extremes, steps, a single spike,
// 1..10 samples, exact powers of two, quantised values. Header-only, shared by the numeric
// harnesses. A failed invariant prints what and aborts (libFuzzer keeps the input).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace gyrocomp::fuzz {

// Reads bytes in order; past the end, zeros.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t Byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::uint64_t U64() {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v = (v << 8) | Byte();
    return v;
  }
  // Any finite double (the bits as given; a NaN or infinity bit pattern becomes 0).
  double Finite() {
    const std::uint64_t bits = U64();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return std::isfinite(v) ? v : 0.0;
  }
  // A "nice" magnitude 10^e, e in [-308, 308], with a sign.
  double Decade() {
    const int e = static_cast<int>(Byte() % 205) * 3 - 306;
    return (Byte() & 1 ? -1.0 : 1.0) * std::pow(10.0, e);
  }
  bool Empty() const { return pos_ >= size_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

inline constexpr int kNumShapes = 10;

// A series of n finite doubles of one shape.
inline std::vector<double> MakeSeries(ByteReader& in, std::size_t n) {
  std::vector<double> x(n, 0.0);
  const int shape = in.Byte() % kNumShapes;
  const double a = in.Decade(), b = in.Finite();
  switch (shape) {
    case 0:  // raw doubles (any finite bit pattern)
      for (double& v : x) v = in.Finite();
      break;
    case 1:  // constant
      std::fill(x.begin(), x.end(), in.Byte() & 1 ? a : b);
      break;
    case 2:  // alternating extremes
      for (std::size_t i = 0; i < n; ++i) x[i] = i % 2 ? std::numeric_limits<double>::max() : -std::numeric_limits<double>::max();
      if (in.Byte() & 1) for (double& v : x) v *= std::ldexp(1.0, -static_cast<int>(in.Byte() % 64));
      break;
    case 3: {  // a step
      const std::size_t at = n == 0 ? 0 : in.Byte() % n;
      for (std::size_t i = 0; i < n; ++i) x[i] = i < at ? 0.0 : a;
      break;
    }
    case 4: {  // a single spike on zeros or on a constant
      const std::size_t at = n == 0 ? 0 : in.Byte() % n;
      const double base = in.Byte() & 1 ? 0.0 : b;
      std::fill(x.begin(), x.end(), base);
      if (n > 0) x[at] = a;
      break;
    }
    case 5:  // subnormals
      for (double& v : x) v = std::ldexp(static_cast<double>(in.Byte()) - 128.0, -1074 + static_cast<int>(in.Byte() % 40));
      break;
    case 6:  // exact powers of two
      for (double& v : x) v = std::ldexp(in.Byte() & 1 ? -1.0 : 1.0, static_cast<int>(in.Byte() % 255) * 8 - 1074 + 2);
      break;
    case 7: {  // quantised: a few levels of one step
      const double q = std::abs(a) > 0 ? std::abs(a) : 1.0;
      for (double& v : x) v = q * (static_cast<int>(in.Byte() % 5) - 2);
      break;
    }
    case 8:  // random values scaled to one decade
      for (double& v : x) v = a * (static_cast<double>(in.Byte()) - 127.5) / 128.0;
      break;
    default:  // smooth ramp plus pseudo-noise, scaled: the shape of a real record
      for (std::size_t i = 0; i < n; ++i) {
        x[i] = a * (0.001 * static_cast<double>(i) + ((static_cast<int>(i * 7919u % 101u)) - 50) / 50.0);
      }
      break;
  }
  for (double& v : x) {
    if (!std::isfinite(v)) v = 0.0;
  }
  return x;
}

// Length: 1..10 one time in four, else up to `max_n`.
inline std::size_t MakeLength(ByteReader& in, std::size_t max_n) {
  const std::uint8_t s = in.Byte();
  if (s % 4 == 0) return 1 + in.Byte() % 10;
  return 1 + (static_cast<std::size_t>(in.Byte()) << 8 | in.Byte()) % max_n;
}

[[noreturn]] inline void Fail(const std::string& what) {
  std::fprintf(stderr, "numeric invariant failed: %s\n", what.c_str());
  std::abort();
}

inline void CheckFinite(std::span<const double> v, const std::string& what) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) Fail(what + "[" + std::to_string(i) + "] = " + std::to_string(v[i]) + " with a success status");
  }
}
inline void CheckFinite(double v, const std::string& what) {
  if (!std::isfinite(v)) Fail(what + " = " + std::to_string(v) + " with a success status");
}

// An error must say what is wrong.
template <typename R>
bool OkOrMessage(const R& r, const char* what) {
  if (r.ok()) return true;
  if (r.error().message.empty()) Fail(std::string(what) + ": an error without a message");
  return false;
}

}  // namespace gyrocomp::fuzz
