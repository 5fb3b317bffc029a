// Threads of the VMD iteration (internal to src/decompose/): RunThreads for one-off parallel
// work (the inverse FFTs), WorkerPool for the hundreds of short rounds of the ADMM loop.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <thread>
#include <vector>

namespace gyrocomp::vmd_internal {

// Runs fn(t) for t = 0..threads-1, fn(0) on the calling thread.
template <class Fn>
void RunThreads(int threads, Fn&& fn) {
  if (threads <= 1) {
    fn(0);
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(threads - 1);
  for (int t = 1; t < threads; ++t) pool.emplace_back([&fn, t] { fn(t); });
  fn(0);
  for (auto& th : pool) th.join();
}

// Persistent workers for the iteration loop: hundreds of short rounds (~70 us of kernel per
// update at N = 20k, K = 6, one thread).
//
// A round is announced by bumping a generation counter and finished by counting down `pending_`;
// each side first spins (a CPU pause per check) for up to kSpin, then blocks in the kernel
// (atomic::wait, a futex). Blocking alone (std::barrier) cost as much per round as the second
// thread saved at N = 20k: a sleeping vCPU takes tens of microseconds to wake in a VM. Spinning
// alone is a disaster when the two threads share a CPU (another process on the second core, or
// the scheduler not having moved the new worker yet): a spinner burns the time its partner needs
// (2-7x slower rounds, docs/explanation/performance.md, "The second core"). So the pool also watches itself: a round
// on all threads that took longer than the caller's share times the thread count (what the
// caller alone would have needed) is a loss; after two such rounds in a row the caller runs the
// next rounds alone (the workers blocked), then tries all threads again, waiting twice as long
// after each failed try (16 .. 1024 rounds). The results are the same bits either way: a round
// computes the same blocks, each into its own partial sums (vmd.cc).
class WorkerPool {
 public:
  explicit WorkerPool(int threads) : threads_(threads) {
    for (int t = 1; t < threads; ++t) workers_.emplace_back([this, t] { Loop(t); });
  }
  ~WorkerPool() {
    stop_.store(true, std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);
    generation_.notify_all();
    for (auto& w : workers_) w.join();
  }
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  // One round: fn(t, n) for t = 0 .. n-1 (fn(0, n) on the caller), n = the pool's threads, or 1
  // while the caller runs rounds alone. Returns when all are done.
  void Run(const std::function<void(int, int)>& fn) {
    if (threads_ <= 1 || alone_left_ > 0) {
      if (alone_left_ > 0) --alone_left_, ++rounds_alone_;
      fn(0, 1);
      return;
    }
    const auto t0 = Clock::now();
    fn_ = &fn;
    pending_.store(threads_ - 1, std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);  // publishes fn_ and pending_
    generation_.notify_all();
    fn(0, threads_);
    const auto t_caller = Clock::now() - t0;
    SpinThenWait(pending_, [this] { return pending_.load(std::memory_order_acquire) == 0; });
    Judge(Clock::now() - t0, t_caller);
  }
  // Rounds the caller ran alone because all threads were slower (diagnostics, tests).
  int rounds_alone() const { return rounds_alone_; }

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr auto kSpin = std::chrono::microseconds(50);
  static constexpr int kFirstAlone = 16, kMaxAlone = 1024;

  // Waits until ready() holds: spinning for up to kSpin, then blocking until `value` changes
  // (ready() only becomes true after a change of `value` that is notified).
  template <class T, class Ready>
  static void SpinThenWait(const std::atomic<T>& value, const Ready& ready) {
    const auto until = Clock::now() + kSpin;
    for (int i = 0;; ++i) {
      if (ready()) return;
      CpuRelax();
      if (i % 16 == 15 && Clock::now() > until) break;
    }
    for (T seen = value.load(std::memory_order_acquire); !ready(); seen = value.load(std::memory_order_acquire)) {
      value.wait(seen, std::memory_order_acquire);
    }
  }
  static void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  }
  // After a round on all threads: a loss when it took longer than the caller alone would have.
  void Judge(Clock::duration round, Clock::duration caller_share) {
    if (round < caller_share * threads_) {
      losses_ = 0;
      next_alone_ = kFirstAlone;
      return;
    }
    if (++losses_ < 2) return;
    losses_ = 0;
    alone_left_ = next_alone_;
    next_alone_ = std::min(2 * next_alone_, kMaxAlone);
  }
  void Loop(int t) {
    std::uint32_t seen = 0;
    for (;;) {
      SpinThenWait(generation_, [this, seen] { return generation_.load(std::memory_order_acquire) != seen; });
      seen = generation_.load(std::memory_order_acquire);
      if (stop_.load(std::memory_order_relaxed)) return;
      (*fn_)(t, threads_);
      if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) pending_.notify_one();
    }
  }

  const int threads_;
  std::atomic<std::uint32_t> generation_{0};  // 32 bits: a futex word
  std::atomic<int> pending_{0};
  std::atomic<bool> stop_{false};
  const std::function<void(int, int)>* fn_ = nullptr;
  int losses_ = 0, alone_left_ = 0, next_alone_ = kFirstAlone, rounds_alone_ = 0;
  std::vector<std::thread> workers_;
};

}  // namespace gyrocomp::vmd_internal
