// The VMD kernel's compiled paths (AVX-512F, AVX2, x86-64 baseline) against a plain scalar
// transcription of Eq. (4) and the sums, operation for operation: they must agree bit for bit
// (the determinism promise of vmd.h: the same bits on any x86-64). Paths this CPU lacks are
// skipped with a message.
#include "vmd_kernel.h"

#include <gtest/gtest.h>

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

TEST(VmdKernel, EveryCompiledPathEqualsTheScalarDefinitionBitForBit) {
  const std::size_t n = 1021;  // 127 full vectors and a tail of 5
  int paths_run = 0;
  for (KernelPath path : {KernelPath::kBaseline, KernelPath::kAvx2, KernelPath::kAvx512f}) {
    const std::string name = path == KernelPath::kBaseline ? "baseline" : path == KernelPath::kAvx2 ? "avx2" : "avx512f";
    if (!KernelPathSupported(path)) {
      std::printf("VmdKernel: %s not supported by this CPU, not checked\n", name.c_str());
      continue;
    }
    ++paths_run;
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
  EXPECT_GE(paths_run, 1);
}

}  // namespace
}  // namespace gyrocomp::vmd_internal
