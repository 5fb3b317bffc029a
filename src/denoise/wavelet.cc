// Discrete wavelet transform with PyWavelets' extension modes and coefficient lengths.
//
// Written from the definitions in include/gyrocomp/wavelet.h (see there): the signal is extended
// into a buffer once, then every output is a plain dot product, so the boundary handling lives in
// one function (ExtendedValue) instead of one code path per mode and per boundary.
#include "gyrocomp/denoise/wavelet.h"

#include <cmath>
#include <cstddef>
#include <string>

namespace gyrocomp {
namespace {

using Index = std::ptrdiff_t;

Index Mod(Index i, Index p) {
  const Index r = i % p;
  return r < 0 ? r + p : r;
}

// Value of the signal x extended beyond its ends by `mode`, at any integer position i.
// (Periodization is handled by the caller as periodic extension of the even-length signal.)
double ExtendedValue(std::span<const double> x, Index i, ExtensionMode mode) {
  const Index n = static_cast<Index>(x.size());
  if (i >= 0 && i < n) return x[static_cast<std::size_t>(i)];
  switch (mode) {
    case ExtensionMode::kSymmetric: {  // period 2n: x0..x(n-1) x(n-1)..x0
      Index k = Mod(i, 2 * n);
      if (k >= n) k = 2 * n - 1 - k;
      return x[static_cast<std::size_t>(k)];
    }
    case ExtensionMode::kReflect: {  // period 2n-2: x0..x(n-1) x(n-2)..x1
      if (n == 1) return x[0];
      Index k = Mod(i, 2 * n - 2);
      if (k >= n) k = 2 * n - 2 - k;
      return x[static_cast<std::size_t>(k)];
    }
    case ExtensionMode::kPeriodic:
    case ExtensionMode::kPeriodization:
      return x[static_cast<std::size_t>(Mod(i, n))];
    case ExtensionMode::kZero:
      return 0.0;
    case ExtensionMode::kConstant:
      return i < 0 ? x.front() : x.back();
  }
  return 0.0;
}

// Extended signal at positions [first, first + count).
std::vector<double> ExtendedBuffer(std::span<const double> x, Index first, std::size_t count,
                                   ExtensionMode mode) {
  std::vector<double> buffer(count);
  for (std::size_t k = 0; k < count; ++k) buffer[k] = ExtendedValue(x, first + static_cast<Index>(k), mode);
  return buffer;
}

// out[o] = sum_j f[j] * ext(i0 + 2 o - j), o < num_out, where ext(p) = buffer[p - first].
void DownsampledConvolution(const std::vector<double>& buffer, Index first, const std::vector<double>& f,
                            Index i0, std::size_t num_out, std::vector<double>* out) {
  out->assign(num_out, 0.0);
  const std::size_t taps = f.size();
  for (std::size_t o = 0; o < num_out; ++o) {
    const Index i = i0 + 2 * static_cast<Index>(o);
    const double* p = buffer.data() + (i - first);  // position i
    double sum = 0.0;
    for (std::size_t j = 0; j < taps; ++j) sum += f[j] * p[-static_cast<Index>(j)];
    (*out)[o] = sum;
  }
}

// Adds the valid part of the upsampled convolution of c with f to out (non-periodization modes):
// out[2(i - F/2 + 1)] += sum_j f[2j] c[i - j], out[... + 1] += sum_j f[2j + 1] c[i - j],
// i = F/2 - 1 .. len(c) - 1.
void AddUpsampledValid(std::span<const double> c, const std::vector<double>& f, std::vector<double>* out) {
  const std::size_t half = f.size() / 2;
  for (std::size_t i = half - 1, o = 0; i < c.size(); ++i, o += 2) {
    double even = 0.0, odd = 0.0;
    for (std::size_t j = 0; j < half; ++j) {
      even += f[2 * j] * c[i - j];
      odd += f[2 * j + 1] * c[i - j];
    }
    (*out)[o] += even;
    (*out)[o + 1] += odd;
  }
}

// Periodization inverse: with E(i) = sum_j f[2j] c[(i - j) mod N], O(i) = sum_j f[2j+1] c[(i-j) mod N]
// and s = F/4: F/2 odd: out[2m] += E(s + m), out[2m+1] += O(s + m);
//              F/2 even: out[2m+1] += E(s + m), out[2m] += O(s + m - 1)   (one-sample shift that
// makes the circular transform perfectly reconstructing, as in PyWavelets).
void AddUpsampledPeriodization(std::span<const double> c, const std::vector<double>& f,
                               std::vector<double>* out) {
  const Index n = static_cast<Index>(c.size());
  const Index half = static_cast<Index>(f.size() / 2);
  const Index s = static_cast<Index>(f.size() / 4);
  auto even_sum = [&](Index i) {
    double sum = 0.0;
    for (Index j = 0; j < half; ++j) sum += f[2 * j] * c[Mod(i - j, n)];
    return sum;
  };
  auto odd_sum = [&](Index i) {
    double sum = 0.0;
    for (Index j = 0; j < half; ++j) sum += f[2 * j + 1] * c[Mod(i - j, n)];
    return sum;
  };
  for (Index m = 0; m < n; ++m) {
    if (half % 2 == 1) {
      (*out)[2 * m] += even_sum(s + m);
      (*out)[2 * m + 1] += odd_sum(s + m);
    } else {
      (*out)[2 * m + 1] += even_sum(s + m);
      (*out)[2 * m] += odd_sum(s + m - 1);
    }
  }
}

}  // namespace

std::optional<ExtensionMode> ParseExtensionMode(std::string_view name) {
  if (name == "symmetric") return ExtensionMode::kSymmetric;
  if (name == "reflect") return ExtensionMode::kReflect;
  if (name == "periodic") return ExtensionMode::kPeriodic;
  if (name == "zero") return ExtensionMode::kZero;
  if (name == "constant") return ExtensionMode::kConstant;
  if (name == "periodization") return ExtensionMode::kPeriodization;
  return std::nullopt;
}

const char* ExtensionModeName(ExtensionMode mode) {
  switch (mode) {
    case ExtensionMode::kSymmetric: return "symmetric";
    case ExtensionMode::kReflect: return "reflect";
    case ExtensionMode::kPeriodic: return "periodic";
    case ExtensionMode::kZero: return "zero";
    case ExtensionMode::kConstant: return "constant";
    case ExtensionMode::kPeriodization: return "periodization";
  }
  return "?";
}

std::size_t DwtCoeffLength(std::size_t n, std::size_t filter_length, ExtensionMode mode) {
  if (n == 0) return 0;
  if (mode == ExtensionMode::kPeriodization) return (n + 1) / 2;
  return (n + filter_length - 1) / 2;
}

int DwtMaxLevel(std::size_t n, std::size_t filter_length) {
  if (filter_length <= 1 || n < filter_length - 1) return 0;
  return static_cast<int>(std::floor(std::log2(static_cast<double>(n) / static_cast<double>(filter_length - 1))));
}

Result<DwtLevel> Dwt(std::span<const double> x, const Wavelet& wavelet, ExtensionMode mode) {
  if (x.empty()) return InvalidInput("Dwt: empty signal");
  const std::size_t taps = wavelet.filter_length();
  const Index f = static_cast<Index>(taps);
  DwtLevel level;
  if (mode == ExtensionMode::kPeriodization) {
    // Odd length: repeat the last sample, then transform circularly.
    std::vector<double> even(x.begin(), x.end());
    if (even.size() % 2 == 1) even.push_back(even.back());
    const std::size_t num_out = even.size() / 2;
    const Index first = -(f - 1);
    const std::size_t count = even.size() + 2 * taps;
    const std::vector<double> buffer = ExtendedBuffer(even, first, count, ExtensionMode::kPeriodic);
    DownsampledConvolution(buffer, first, wavelet.dec_lo, f / 2, num_out, &level.approximation);
    DownsampledConvolution(buffer, first, wavelet.dec_hi, f / 2, num_out, &level.detail);
    return level;
  }
  const std::size_t num_out = DwtCoeffLength(x.size(), taps, mode);
  const Index first = -(f - 1);
  const std::size_t count = x.size() + 2 * (taps - 1) + 1;
  const std::vector<double> buffer = ExtendedBuffer(x, first, count, mode);
  DownsampledConvolution(buffer, first, wavelet.dec_lo, 1, num_out, &level.approximation);
  DownsampledConvolution(buffer, first, wavelet.dec_hi, 1, num_out, &level.detail);
  return level;
}

Result<std::vector<double>> Idwt(std::span<const double> approximation, std::span<const double> detail,
                                 const Wavelet& wavelet, ExtensionMode mode) {
  if (approximation.size() != detail.size()) {
    return InvalidArgument("Idwt: approximation has " + std::to_string(approximation.size()) +
                           " coefficients but detail has " + std::to_string(detail.size()));
  }
  const std::size_t n = approximation.size();
  const std::size_t taps = wavelet.filter_length();
  if (n == 0) return InvalidArgument("Idwt: no coefficients");
  if (mode == ExtensionMode::kPeriodization) {
    std::vector<double> out(2 * n, 0.0);
    AddUpsampledPeriodization(approximation, wavelet.rec_lo, &out);
    AddUpsampledPeriodization(detail, wavelet.rec_hi, &out);
    return out;
  }
  if (n < taps / 2) {
    return InvalidArgument("Idwt: " + std::to_string(n) + " coefficients per band, " + wavelet.name +
                           " needs at least " + std::to_string(taps / 2) + " in mode " +
                           ExtensionModeName(mode));
  }
  std::vector<double> out(2 * n + 2 - taps, 0.0);
  AddUpsampledValid(approximation, wavelet.rec_lo, &out);
  AddUpsampledValid(detail, wavelet.rec_hi, &out);
  return out;
}

Result<WaveletDecomposition> WaveDec(std::span<const double> x, const Wavelet& wavelet,
                                     ExtensionMode mode, std::optional<int> level) {
  if (x.empty()) return InvalidInput("WaveDec: empty signal");
  const int max_level = DwtMaxLevel(x.size(), wavelet.filter_length());
  const int depth = level.value_or(max_level);
  if (depth < 0 || depth > max_level) {
    return InvalidArgument("wavelet level " + std::to_string(depth) + " is out of range for " +
                           std::to_string(x.size()) + " samples with " + wavelet.name +
                           ": the deepest level is " + std::to_string(max_level));
  }
  WaveletDecomposition d;
  d.wavelet = wavelet.name;
  d.mode = mode;
  d.signal_length = x.size();
  d.approximation.assign(x.begin(), x.end());
  d.details.reserve(static_cast<std::size_t>(depth));
  for (int l = 1; l <= depth; ++l) {
    Result<DwtLevel> one = Dwt(d.approximation, wavelet, mode);
    if (!one.ok()) return one.error();
    d.approximation = std::move(one->approximation);
    d.details.push_back(std::move(one->detail));
  }
  return d;
}

Result<std::vector<double>> WaveRec(const WaveletDecomposition& d, const Wavelet& wavelet) {
  std::vector<double> a = d.approximation;
  for (int l = d.level(); l >= 1; --l) {
    const std::vector<double>& detail = d.details[static_cast<std::size_t>(l - 1)];
    // An odd-length level leaves one extra sample in the reconstruction: drop it (as pywt).
    if (a.size() == detail.size() + 1) a.pop_back();
    if (a.size() != detail.size()) {
      return InvalidArgument("WaveRec: level " + std::to_string(l) + " has " + std::to_string(detail.size()) +
                             " detail coefficients but the approximation has " + std::to_string(a.size()));
    }
    Result<std::vector<double>> up = Idwt(a, detail, wavelet, d.mode);
    if (!up.ok()) return up.error();
    a = std::move(*up);
  }
  if (a.size() < d.signal_length) {
    return InvalidArgument("WaveRec: reconstruction has " + std::to_string(a.size()) +
                           " samples, fewer than the signal's " + std::to_string(d.signal_length));
  }
  a.resize(d.signal_length);
  return a;
}

Result<std::vector<double>> WaveRec(const WaveletDecomposition& d) {
  Result<Wavelet> wavelet = MakeWavelet(d.wavelet);
  if (!wavelet.ok()) return wavelet.error();
  return WaveRec(d, *wavelet);
}

}  // namespace gyrocomp
