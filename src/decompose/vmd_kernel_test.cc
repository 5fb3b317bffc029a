// The VMD kernel's compiled paths (AVX-512F, AVX2, x86-64 baseline) against a plain scalar
// transcription of Eq. (4) and the sums, operation for operation: they must agree bit for bit
// (the determinism promise of vmd.h: the same bits on any x86-64). Paths this CPU lacks are
// skipped with a message.
#include "vmd_kernel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace gyrocomp::vmd_internal {
namespace {

struct Arrays {
  std::vector<double> freq, f_re, f_im, l_re, l_im, prev_re, prev_im, old_re, old_im, s_re, s_im, u_re, u_im;
  explicit Arrays(std::size_t n) {
    std::mt19937 rng(11);
    std::normal_distribution<double> g(0, 1);
    for (auto* v : {&f_re, &f_im, &l_re, &l_im, &prev_re, &prev_im, &old_re, &old_im, &s_re, &s_im}) {
      v->resize(n);
      for (double& x : *v) x = g(rng);
    }
    freq.resize(n);
    for (std::size_t j = 0; j < n; ++j) freq[j] = 0.5 * j / n;
    u_re.assign(n, 0.0);
    u_im.assign(n, 0.0);
  }
  ModeChunk Chunk(bool lambda) {
    return {freq.data(), f_re.data(), f_im.data(), lambda ? l_re.data() : nullptr, lambda ? l_im.data() : nullptr,
            prev_re.data(), prev_im.data(), old_re.data(), old_im.data(), s_re.data(), s_im.data(),
            u_re.data(), u_im.data()};
  }
};

// Eq. (4) and the sums, one bin at a time, lane j mod kLanes (vmd_kernel.h).
void Scalar(Arrays& a, bool lambda, double wk, double alpha, LaneSums& acc) {
  for (std::size_t j = 0; j < a.freq.size(); ++j) {
    const std::size_t l = j % kLanes;
    const double sr = (a.prev_re[j] + a.s_re[j]) - a.old_re[j];
    const double si = (a.prev_im[j] + a.s_im[j]) - a.old_im[j];
    a.s_re[j] = sr;
    a.s_im[j] = si;
    const double d = a.freq[j] - wk;
    const double rcp = 1.0 / (1.0 + alpha * (d * d));
    double nr = a.f_re[j] - sr, ni = a.f_im[j] - si;
    if (lambda) {
      nr = nr - a.l_re[j] * 0.5;
      ni = ni - a.l_im[j] * 0.5;
    }
    const double ur = nr * rcp, ui = ni * rcp;
    a.u_re[j] = ur;
    a.u_im[j] = ui;
    const double pw = ur * ur + ui * ui;
    acc.freq_power[l] += a.freq[j] * pw;
    acc.power[l] += pw;
    const double dr = ur - a.old_re[j], di = ui - a.old_im[j];
    acc.diff[l] += dr * dr + di * di;
    acc.old_power[l] += a.old_re[j] * a.old_re[j] + a.old_im[j] * a.old_im[j];
  }
}

// The kernel paths this CPU runs (the baseline at least); the others are printed as not checked.
std::vector<KernelPath> SupportedPaths() {
  std::vector<KernelPath> out;
  for (KernelPath path : {KernelPath::kBaseline, KernelPath::kAvx2, KernelPath::kAvx512f}) {
    if (KernelPathSupported(path)) {
      out.push_back(path);
    } else {
      std::printf("VmdKernel: %s not supported by this CPU, not checked\n", KernelPathName(path));
    }
  }
  return out;
}

TEST(VmdKernel, EveryCompiledPathEqualsTheScalarDefinitionBitForBit) {
  const std::size_t n = 1021;  // 127 full vectors and a tail of 5
  const std::vector<KernelPath> paths = SupportedPaths();
  EXPECT_GE(paths.size(), 1u);
  for (KernelPath path : paths) {
    const std::string name = KernelPathName(path);
    for (bool lambda : {false, true}) {
      SCOPED_TRACE(name + (lambda ? " with lambda" : " without lambda"));
      Arrays expect(n), got(n);
      LaneSums se, sg;
      se.Clear();
      sg.Clear();
      Scalar(expect, lambda, 0.13, 2000.0, se);
      UpdateModeChunkOn(path, got.Chunk(lambda), n, 0.13, 2000.0, sg);
      EXPECT_EQ(got.u_re, expect.u_re);
      EXPECT_EQ(got.u_im, expect.u_im);
      EXPECT_EQ(got.s_re, expect.s_re);
      EXPECT_EQ(got.s_im, expect.s_im);
      for (std::size_t l = 0; l < kLanes; ++l) {
        EXPECT_EQ(sg.freq_power[l], se.freq_power[l]) << l;
        EXPECT_EQ(sg.power[l], se.power[l]) << l;
        EXPECT_EQ(sg.diff[l], se.diff[l]) << l;
        EXPECT_EQ(sg.old_power[l], se.old_power[l]) << l;
      }
    }
  }
}

// ---- the bin-major kernel (all modes of a bin) -------------------------------------------------

struct ModeArrays {
  std::size_t n, K;
  std::vector<double> freq, l_re, l_im, r_re, r_im, u_re, u_im;  // u: K x n, mode-major
  ModeArrays(std::size_t bins, std::size_t modes) : n(bins), K(modes) {
    std::mt19937 rng(5 + modes);
    std::normal_distribution<double> g(0, 1);
    for (auto* v : {&l_re, &l_im, &r_re, &r_im}) {
      v->resize(n);
      for (double& x : *v) x = g(rng);
    }
    for (auto* v : {&u_re, &u_im}) {
      v->resize(n * K);
      for (double& x : *v) x = g(rng);
    }
    freq.resize(n);
    for (std::size_t j = 0; j < n; ++j) freq[j] = 0.5 * j / n;
  }
  // In place: src = dst.
  BinChunk Chunk(bool lambda) {
    return {freq.data(), lambda ? l_re.data() : nullptr, lambda ? l_im.data() : nullptr, r_re.data(), r_im.data(),
            u_re.data(), u_im.data(), u_re.data(), u_im.data(), n};
  }
};

// The definition, one bin at a time: D_k, the reciprocals (batch inversion as documented in
// vmd_kernel.h, or direct), then Eq. (4) per mode on the residual r = f - sum_uk.
void ScalarAllModes(ModeArrays& a, bool lambda, StopSums stop, bool batch, const std::vector<double>& omega,
                    double alpha, std::vector<LaneSums>& acc) {
  const std::size_t K = a.K;
  for (std::size_t j = 0; j < a.n; ++j) {
    const std::size_t l = j % kLanes;
    std::vector<double> D(K), P(K), rcp(K);
    for (std::size_t k = 0; k < K; ++k) {
      const double d = a.freq[j] - omega[k];
      D[k] = 1.0 + alpha * (d * d);
    }
    if (batch) {
      P[0] = D[0];
      for (std::size_t k = 1; k < K; ++k) P[k] = P[k - 1] * D[k];
      double inv = 1.0 / P[K - 1];
      for (std::size_t k = K - 1; k > 0; --k) {
        rcp[k] = inv * P[k - 1];
        inv = inv * D[k];
      }
      rcp[0] = inv;
    } else {
      for (std::size_t k = 0; k < K; ++k) rcp[k] = 1.0 / D[k];
    }
    double pr = a.u_re[(K - 1) * a.n + j], pi = a.u_im[(K - 1) * a.n + j];
    double rr = a.r_re[j], ri = a.r_im[j];
    for (std::size_t k = 0; k < K; ++k) {
      const double o_re = a.u_re[k * a.n + j], o_im = a.u_im[k * a.n + j];
      rr = (rr - pr) + o_re;
      ri = (ri - pi) + o_im;
      double nr = rr, ni = ri;
      if (lambda) {
        nr = nr - a.l_re[j] * 0.5;
        ni = ni - a.l_im[j] * 0.5;
      }
      const double ur = nr * rcp[k], ui = ni * rcp[k];
      a.u_re[k * a.n + j] = ur;
      a.u_im[k * a.n + j] = ui;
      const double pw = ur * ur + ui * ui;
      acc[k].freq_power[l] += a.freq[j] * pw;
      acc[k].power[l] += pw;
      if (stop != StopSums::kNone) {
        const double dr = ur - o_re, di = ui - o_im;
        acc[k].diff[l] += dr * dr + di * di;
      }
      if (stop == StopSums::kRelative) acc[k].old_power[l] += o_re * o_re + o_im * o_im;
      pr = ur;
      pi = ui;
    }
    a.r_re[j] = rr;
    a.r_im[j] = ri;
  }
}

TEST(VmdKernel, BinMajorPathsEqualTheScalarDefinitionBitForBitForEveryK) {
  const std::size_t n = 1021;  // 127 full vectors and a tail of 5
  const std::vector<KernelPath> paths = SupportedPaths();
  EXPECT_GE(paths.size(), 1u);
  for (KernelPath path : paths) {
    const std::string name = KernelPathName(path);
    for (int K = 1; K <= kMaxModesAtOnce; ++K) {
      std::vector<double> omega(K);
      for (int k = 0; k < K; ++k) omega[k] = 0.5 * k / K + 0.01;
      for (int variant = 0; variant < 24; ++variant) {
        const bool lambda = variant & 1, batch = variant & 2, two_pass = variant & 4;
        const StopSums stop = static_cast<StopSums>(variant / 8);  // none, absolute, relative
        SCOPED_TRACE(name + " K=" + std::to_string(K) + " lambda=" + std::to_string(lambda) +
                     " stop=" + std::to_string(variant / 8) + " batch=" + std::to_string(batch) +
                     " two_pass=" + std::to_string(two_pass));
        ModeArrays expect(n, K), got(n, K);
        // Sums start from nonzero values: kNone must leave diff and old_power as they are.
        std::vector<LaneSums> se(K), sg(K);
        for (int k = 0; k < K; ++k) {
          for (std::size_t l = 0; l < kLanes; ++l) {
            const double v = 1.0 + k + 0.125 * l;
            se[k].freq_power[l] = se[k].power[l] = se[k].diff[l] = se[k].old_power[l] = v;
            sg[k].freq_power[l] = sg[k].power[l] = sg[k].diff[l] = sg[k].old_power[l] = v;
          }
        }
        ScalarAllModes(expect, lambda, stop, batch, omega, 2000.0, se);
        BinChunk chunk = got.Chunk(lambda);
        chunk.two_pass = two_pass;
        UpdateBinChunkOn(path, chunk, n, K, omega.data(), 2000.0, batch, stop, sg.data());
        ASSERT_EQ(got.u_re, expect.u_re);
        ASSERT_EQ(got.u_im, expect.u_im);
        ASSERT_EQ(got.r_re, expect.r_re);
        ASSERT_EQ(got.r_im, expect.r_im);
        for (int k = 0; k < K; ++k) {
          for (std::size_t l = 0; l < kLanes; ++l) {
            ASSERT_EQ(sg[k].freq_power[l], se[k].freq_power[l]) << k << " " << l;
            ASSERT_EQ(sg[k].power[l], se[k].power[l]) << k << " " << l;
            ASSERT_EQ(sg[k].diff[l], se[k].diff[l]) << k << " " << l;
            ASSERT_EQ(sg[k].old_power[l], se[k].old_power[l]) << k << " " << l;
          }
        }
      }
    }
  }
}

// Batch inversion against one division per reciprocal. Mode 0 isolates the reciprocal: its
// residual (r - u_{K-1}^old) + u_0^old is computed identically both ways, so u_0 = n rcp_0 differs
// only through rcp_0, which has the longest chain of the batch: K - 1 prefix products, the
// division, K - 1 backward products (2K - 1 roundings of <= 2^-53 relative each), plus the
// rounding of n rcp_0 and of the direct 1 / D_0: |du_0| <= (2K + 1) 2^-53 |u_0| to first order;
// the bound below doubles it for second-order terms. (Later modes' u differ also through the
// residual chain, where cancellation can amplify a relative difference: not a reciprocal property.)
TEST(VmdKernel, BatchInversionAgreesWithDirectDivisionToAFewRoundings) {
  const std::size_t n = 1024;
  for (int K : {2, 6, 8}) {
    std::vector<double> omega(K);
    for (int k = 0; k < K; ++k) omega[k] = 0.5 * k / K;
    ModeArrays batch(n, K), direct(n, K);
    std::vector<LaneSums> sb(K), sd(K);
    for (int k = 0; k < K; ++k) sb[k].Clear(), sd[k].Clear();
    UpdateBinChunk(batch.Chunk(false), n, K, omega.data(), 2000.0, true, StopSums::kAbsolute, sb.data());
    UpdateBinChunk(direct.Chunk(false), n, K, omega.data(), 2000.0, false, StopSums::kAbsolute, sd.data());
    const double bound = 2 * (2 * K + 1) * 0x1p-53;
    double worst = 0;
    for (std::size_t i = 0; i < n; ++i) {  // mode 0
      worst = std::max(worst, std::abs(batch.u_re[i] - direct.u_re[i]) / std::abs(direct.u_re[i]));
      worst = std::max(worst, std::abs(batch.u_im[i] - direct.u_im[i]) / std::abs(direct.u_im[i]));
    }
    EXPECT_LE(worst, bound) << "K = " << K;
    EXPECT_GT(worst, 0) << "K = " << K << ": the two ways should round differently somewhere";
  }
}

// The overflow guard: (1 + alpha / 4)^K must stay below 2^1000 for the prefix products.
TEST(VmdKernel, BatchInversionIsRefusedWhereItsProductsCouldOverflow) {
  EXPECT_TRUE(BatchInversionSafe(6, 2000.0));
  EXPECT_TRUE(BatchInversionSafe(8, 1e30));    // (2.5e29)^8 ~ 1.5e235
  EXPECT_FALSE(BatchInversionSafe(8, 1e40));   // (2.5e39)^8 ~ 1.5e315: overflow
  EXPECT_FALSE(BatchInversionSafe(2, 1e300));
  // With the fallback the huge-alpha case stays finite (each mode ~ n / D).
  const std::size_t n = 64;
  ModeArrays a(n, 8);
  std::vector<double> omega(8);
  for (int k = 0; k < 8; ++k) omega[k] = 0.06 * k;
  std::vector<LaneSums> s(8);
  for (auto& x : s) x.Clear();
  UpdateBinChunk(a.Chunk(false), n, 8, omega.data(), 1e40, BatchInversionSafe(8, 1e40), StopSums::kAbsolute, s.data());
  for (double v : a.u_re) EXPECT_TRUE(std::isfinite(v));
}

}  // namespace
}  // namespace gyrocomp::vmd_internal
