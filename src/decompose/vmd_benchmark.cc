// VMD timings (goals: kernel <= 0.5 ns per bin-update at N = 20,000; N = 1,000,000,
// K = 6 converged within 8 s and 400 MB on the 2-core machine).
// Input: a gyro-like record, white noise (ARW) plus a slow drift, reference defaults (alpha 2000,
// tau 0, tol 1e-7, uniform init, 500 max iterations).
//   build/vmd_benchmark --benchmark_filter=VmdKernel     # ns per bin-update (counter ns_per_bin_update)
//   build/vmd_benchmark --benchmark_filter=Vmd/          # whole DecomposeVmd
// Peak memory: /usr/bin/time -v build/vmd_benchmark --benchmark_filter='Vmd/1000000'
// A bin-update is one mode at one bin of the one-sided spectrum in one iteration (Eq. 4 with the
// Eq. 5 / stopping-rule sums): K x H per iteration, H = N for the mirror-extended signal.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

#include "gyrocomp/decompose/vmd.h"
#include "vmd_kernel.h"
#include "vmd_spectrum.h"
#include "vmd_threads.h"

namespace {

std::vector<double> GyroLike(std::size_t n) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0, 0.05);
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = 0.2 * std::sin(2 * std::numbers::pi * i / (0.7 * n)) + 0.01 * i / n + g(rng);
  }
  return x;
}

// The least disturbed repetition: on a shared machine the best estimate of the code's cost.
double MinOf(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

void BM_Vmd(benchmark::State& state) {
  const auto x = GyroLike(static_cast<std::size_t>(state.range(0)));
  gyrocomp::VmdOptions opt;
  opt.num_modes = 6;
  if (state.range(1) > 0) opt.num_threads = static_cast<int>(state.range(1));
  int iterations = 0;
  double bin_updates = 0;
  for (auto _ : state) {
    auto r = gyrocomp::DecomposeVmd(x, opt);
    iterations = r.ok() ? r->summary.iterations : -1;
    bin_updates += r.ok() ? 6.0 * (r->summary.extended_length / 2) * iterations : 0;
    benchmark::DoNotOptimize(r.ok());
  }
  state.counters["vmd_iterations"] = iterations;
  // Whole DecomposeVmd (FFTs included) per bin-update, wall time.
  state.counters["ns_per_bin_update"] =
      benchmark::Counter(bin_updates * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
// Second argument: threads (0 = automatic).
BENCHMARK(BM_Vmd)
    ->Args({20000, 0})
    ->Args({20000, 1})
    ->Args({100000, 0})
    ->Args({1000000, 0})
    ->Args({1000000, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The average over a real decomposition, CPU time: gyro-like N = 20,000 (359 updates), K = 6,
// one thread, the whole DecomposeVmd (the forward FFT, the updates with the stopping-rule sums
// computed or skipped as StopSchedule decides, the Eq. 5 reductions, the 6 inverse FFTs) per
// bin-update: an upper bound on the kernel's average over the iterations. Not UseRealTime, so
// the ns_per_bin_update rate is per CPU second (robust on a loaded machine). Argument 1: 0 =
// DecomposeVmd's schedule, 1 = the stopping sums on every update (VmdTuning::stop_schedule off),
// 2 = one update only (max_iterations 2): the fixed costs. The per-update cost of a real
// decomposition is (time of /0 - time of /2) / (updates of /0 - 1), which leaves out the
// transforms, planning and allocation (docs/explanation/performance.md).
void BM_VmdCpu(benchmark::State& state) {
  const auto x = GyroLike(static_cast<std::size_t>(state.range(0)));
  gyrocomp::VmdOptions opt;
  opt.num_modes = 6;
  opt.num_threads = 1;
  gyrocomp::vmd_internal::VmdTuning tuning;
  tuning.stop_schedule = state.range(1) != 1;
  if (state.range(1) == 2) opt.max_iterations = 2;
  double bin_updates = 0;
  int iterations = 0;
  for (auto _ : state) {
    auto r = gyrocomp::vmd_internal::DecomposeVmdTuned(x, opt, tuning, nullptr);
    iterations = r.ok() ? r->summary.iterations : -1;
    bin_updates += r.ok() ? 6.0 * (r->summary.extended_length / 2) * iterations : 0;
    benchmark::DoNotOptimize(r.ok());
  }
  state.counters["vmd_iterations"] = iterations;
  state.counters["ns_per_bin_update"] =
      benchmark::Counter(bin_updates * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.SetLabel(gyrocomp::vmd_internal::KernelIsa());
}
// N = 16384: H a multiple of 512, where an unpadded mode stride (4 KiB multiple) 4K-aliases
// (vmd.cc: ModeStride).
BENCHMARK(BM_VmdCpu)
    ->Args({20000, 0})
    ->Args({20000, 1})
    ->Args({20000, 2})
    ->Args({16384, 0})
    ->Unit(benchmark::kMillisecond);

// The updates of a real decomposition (gyro-like N, K = 6, the defaults), wall time from the end
// of update 1 to the end of the last (VmdOptions::on_iteration): the kernel with its stopping
// sums where the schedule computes them, the Eq. (5) reductions, the thread coordination, per
// bin-update; the transforms, planning and first allocations are left out. Second argument:
// threads (0 = automatic).
void BM_VmdUpdates(benchmark::State& state) {
  const auto x = GyroLike(static_cast<std::size_t>(state.range(0)));
  gyrocomp::VmdOptions opt;
  opt.num_modes = 6;
  if (state.range(1) > 0) opt.num_threads = static_cast<int>(state.range(1));
  using Clock = std::chrono::steady_clock;
  Clock::time_point first, last;
  int last_n = 0;
  opt.on_iteration = [&](int n, double) {
    if (n == 1) first = Clock::now();
    last = Clock::now();
    last_n = n;
  };
  double seconds = 0, bin_updates = 0;
  int threads = 0;
  for (auto _ : state) {
    auto r = gyrocomp::DecomposeVmd(x, opt);
    if (!r.ok() || last_n < 2) {
      state.SkipWithError("decomposition failed");
      return;
    }
    const double s = std::chrono::duration<double>(last - first).count();
    seconds += s;
    bin_updates += 6.0 * (r->summary.extended_length / 2) * (last_n - 1);
    threads = r->summary.threads_used;
    state.SetIterationTime(s);
  }
  state.counters["ns_per_bin_update"] = seconds / bin_updates * 1e9;
  state.counters["threads"] = threads;
  state.counters["updates"] = last_n;
}
BENCHMARK(BM_VmdUpdates)
    ->Args({20000, 1})
    ->Args({20000, 0})
    ->ComputeStatistics("min", MinOf)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

// The kernel alone, one thread, K = 6 modes over H bins in 256-bin chunks as DecomposeVmd walks
// them. Second argument: 0 = the bin-major kernel updating the iterate in place (DecomposeVmd's
// path for K <= 8: per bin-update 16 bytes of the iterate read and 16 written back), 1 = the
// mode-major kernel with two iterates (the path for K > 8, and the kernel before the in-place
// iterate: 16 bytes read, 16 written to another array). H = 20,000 (N = 20k: the in-place iterate,
// 1.9 MB, lives in L2/L3) and H = 1,000,000 (memory-bound: 96 MB of iterate per pass).
// ns_per_bin_update and bytes_per_second use the wall time; on a loaded machine divide the CPU
// time by K H instead, or take the "min" statistic of repetitions (the least disturbed run).
// BM_VmdKernelPath: the same cases with a third argument, the instruction-set path: 1 = AVX-512F,
// 2 = AVX2, 3 = the x86-64 baseline (skipped when the CPU lacks it), so that an AVX-512 machine
// measures what CPUs without it run. BM_VmdKernel uses the dispatcher's choice for this CPU.
void KernelCase(benchmark::State& state, int64_t path_argument) {
  using namespace gyrocomp::vmd_internal;
  const KernelPath path = path_argument == 0   ? BestKernelPath()
                          : path_argument == 1 ? KernelPath::kAvx512f
                          : path_argument == 2 ? KernelPath::kAvx2
                                               : KernelPath::kBaseline;
  if (!KernelPathSupported(path)) {
    state.SkipWithError("this CPU lacks the instruction set of the path asked for");
    return;
  }
  const std::size_t H = static_cast<std::size_t>(state.range(0));
  const bool mode_major = state.range(1) == 1;
  // Argument 2: the bin-major kernel without the stopping-rule sums (DecomposeVmd's updates that
  // StopSchedule skips). 0 and 2 pick one or two passes as DecomposeVmd does (UseTwoPass: two at
  // 20k, one at 1M); 3 = 0 forced to one pass.
  const StopSums stop = state.range(1) == 2 ? StopSums::kNone : StopSums::kAbsolute;
  const int K = 6;
  const std::size_t KH = K * H;
  std::mt19937 rng(1);
  std::normal_distribution<double> g(0, 1);
  // 64-byte aligned, as DecomposeVmd's arrays (AlignedVector).
  using gyrocomp::vmd_internal::AlignedVector;
  AlignedVector freq(H), f_re(H), f_im(H), s_re(H, 0), s_im(H, 0);
  AlignedVector a_re(KH), a_im(KH), b_re(mode_major ? KH : 0, 0), b_im(mode_major ? KH : 0, 0);
  for (std::size_t j = 0; j < H; ++j) {
    freq[j] = 0.5 * j / H;
    f_re[j] = g(rng);
    f_im[j] = g(rng);
  }
  for (std::size_t j = 0; j < KH; ++j) {
    a_re[j] = g(rng);
    a_im[j] = g(rng);
  }
  const double omega[K] = {0.0, 0.05, 0.1, 0.15, 0.2, 0.25};
  std::vector<LaneSums> sums(K);
  for (auto _ : state) {
    for (auto& s : sums) s.Clear();
    for (std::size_t c0 = 0; c0 < H; c0 += 256) {
      const std::size_t n = std::min<std::size_t>(256, H - c0);
      if (!mode_major) {
        BinChunk c{freq.data() + c0, nullptr, nullptr, f_re.data() + c0, f_im.data() + c0, a_re.data() + c0,
                   a_im.data() + c0, a_re.data() + c0, a_im.data() + c0, H};
        c.two_pass = state.range(1) == 3 ? false : UseTwoPass(K, H);  // as DecomposeVmd, or forced one-pass
        UpdateBinChunkOn(path, c, n, K, omega, 2000.0, true, stop, sums.data());
        continue;
      }
      for (int k = 0; k < K; ++k) {
        const std::size_t kk = k * H + c0, prev = (k == 0 ? (K - 1) * H : kk - H) + (k == 0 ? c0 : 0);
        ModeChunk c{freq.data() + c0, f_re.data() + c0, f_im.data() + c0, nullptr, nullptr,
                    (k == 0 ? a_re.data() : b_re.data()) + prev, (k == 0 ? a_im.data() : b_im.data()) + prev,
                    a_re.data() + kk, a_im.data() + kk, s_re.data() + c0, s_im.data() + c0,
                    b_re.data() + kk, b_im.data() + kk};
        UpdateModeChunkOn(path, c, n, omega[k], 2000.0, sums[k]);
      }
    }
    benchmark::DoNotOptimize(sums.data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(KernelPathName(path));
  state.counters["ns_per_bin_update"] = benchmark::Counter(
      static_cast<double>(KH) * state.iterations() * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * KH * 4 * sizeof(double));
}
void BM_VmdKernel(benchmark::State& state) { KernelCase(state, 0); }
BENCHMARK(BM_VmdKernel)
    ->Args({20000, 0})
    ->Args({20000, 1})
    ->Args({20000, 2})
    ->Args({20000, 3})
    ->Args({1000000, 0})
    ->Args({1000000, 1})
    ->Args({1000000, 2})
    ->ComputeStatistics("min", MinOf)
    ->UseRealTime();
void BM_VmdKernelPath(benchmark::State& state) { KernelCase(state, state.range(2)); }
BENCHMARK(BM_VmdKernelPath)
    ->Args({20000, 0, 2})
    ->Args({20000, 2, 2})
    ->Args({20000, 1, 2})
    ->Args({20000, 0, 3})
    ->Args({20000, 2, 3})
    ->Args({20000, 1, 3})
    ->ComputeStatistics("min", MinOf)
    ->UseRealTime();

// The kernel in rounds as DecomposeVmd runs it: H = 20,000 bins, K = 6, in place, 2048-bin
// blocks split between the threads of a WorkerPool (which runs rounds alone when two threads are
// slower), the Eq. (5) sums per block; wall time per bin-update over the round, coordination
// included. Arguments: H, threads, 0 = without the stopping-rule sums / 1 = with them. The
// kernel goal (<= 0.5 ns per bin-update at N = 20k on this 2-core machine) is this wall time.
void BM_VmdKernelRounds(benchmark::State& state) {
  using namespace gyrocomp::vmd_internal;
  const std::size_t H = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const StopSums stop = state.range(2) == 1 ? StopSums::kAbsolute : StopSums::kNone;
  const int K = 6;
  const std::size_t stride = H + 32, block_bins = 2048, blocks = (H + block_bins - 1) / block_bins;
  std::mt19937 rng(1);
  std::normal_distribution<double> g(0, 1);
  AlignedVector freq(H), r_re(H), r_im(H), a_re(K * stride), a_im(K * stride);
  for (std::size_t j = 0; j < H; ++j) {
    freq[j] = 0.5 * j / H;
    r_re[j] = g(rng);
    r_im[j] = g(rng);
  }
  for (std::size_t j = 0; j < K * stride; ++j) {
    a_re[j] = g(rng);
    a_im[j] = g(rng);
  }
  const double omega[K] = {0.0, 0.05, 0.1, 0.15, 0.2, 0.25};
  std::vector<LaneSums> sums(blocks * K);
  const std::function<void(int, int)> round = [&](int t, int of) {
    for (std::size_t b = blocks * t / of; b < blocks * (t + 1) / of; ++b) {
      LaneSums* bs = &sums[b * K];
      for (int k = 0; k < K; ++k) bs[k].Clear();
      for (std::size_t c0 = b * block_bins; c0 < std::min(H, (b + 1) * block_bins); c0 += 256) {
        const std::size_t n = std::min<std::size_t>(256, H - c0);
        BinChunk c{freq.data() + c0, nullptr, nullptr, r_re.data() + c0, r_im.data() + c0, a_re.data() + c0,
                   a_im.data() + c0, a_re.data() + c0, a_im.data() + c0, stride};
        c.two_pass = UseTwoPass(K, stride);
        UpdateBinChunk(c, n, K, omega, 2000.0, true, stop, bs);
      }
    }
  };
  WorkerPool pool(threads);
  for (auto _ : state) {
    pool.Run(round);
    benchmark::DoNotOptimize(sums.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_bin_update"] = benchmark::Counter(
      static_cast<double>(K * H) * state.iterations() * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["rounds_alone"] = pool.rounds_alone();
  state.SetLabel(KernelIsa());
}
BENCHMARK(BM_VmdKernelRounds)
    ->Args({20000, 1, 0})
    ->Args({20000, 2, 0})
    ->Args({20000, 1, 1})
    ->Args({20000, 2, 1})
    ->ComputeStatistics("min", MinOf)
    ->UseRealTime();

// The machine's streaming bandwidth for the kernel's memory patterns, n = 6,000,000 doubles per
// array (the K H = 6 x 10^6 of the N = 1M kernel case). Argument 0: in place, re and im arrays
// each read and written back (y = y + 1; the bin-major kernel's pattern); 1: two arrays read, two
// others written (y = x + 1; the mode-major kernel's pattern). Both count 32 bytes per element
// pair, as BM_VmdKernel does per bin-update, so their bytes_per_second compare directly
// ("within 1.5x of the memory bandwidth").
void BM_MemoryStream(benchmark::State& state) {
  const std::size_t n = 6000000;
  const bool two_arrays = state.range(0) == 1;
  std::vector<double> a_re(n, 1.0), a_im(n, 2.0), b_re(two_arrays ? n : 0, 0.0), b_im(two_arrays ? n : 0, 0.0);
  double* out_re = two_arrays ? b_re.data() : a_re.data();
  double* out_im = two_arrays ? b_im.data() : a_im.data();
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) {
      out_re[i] = a_re[i] + 1.0;
      out_im[i] = a_im[i] + 1.0;
    }
    benchmark::DoNotOptimize(out_re);
    benchmark::DoNotOptimize(out_im);
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * n * 4 * sizeof(double));
}
BENCHMARK(BM_MemoryStream)->Arg(0)->Arg(1)->UseRealTime();

}  // namespace
