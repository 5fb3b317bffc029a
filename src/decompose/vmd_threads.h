// Threads of the VMD iteration (internal to src/decompose/): RunThreads for one-off parallel
// work (the inverse FFTs), WorkerPool for the hundreds of short rounds of the ADMM loop.
#pragma once

#include <atomic>
#include <barrier>
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

// Persistent workers for the iteration loop (hundreds of short rounds: starting threads each
// round would cost a noticeable part of a round at N ~ 10^4).
class WorkerPool {
 public:
  explicit WorkerPool(int threads) : threads_(threads), start_(threads), done_(threads) {
    for (int t = 1; t < threads; ++t) workers_.emplace_back([this, t] { Loop(t); });
  }
  ~WorkerPool() {
    stop_ = true;
    if (threads_ > 1) start_.arrive_and_wait();
    for (auto& w : workers_) w.join();
  }
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;
  // fn(t) on every thread t, fn(0) on the caller; returns when all are done.
  void Run(const std::function<void(int)>& fn) {
    fn_ = &fn;
    if (threads_ > 1) start_.arrive_and_wait();
    fn(0);
    if (threads_ > 1) done_.arrive_and_wait();
  }

 private:
  void Loop(int t) {
    for (;;) {
      start_.arrive_and_wait();
      if (stop_) return;
      (*fn_)(t);
      done_.arrive_and_wait();
    }
  }
  int threads_;
  std::barrier<> start_, done_;
  std::atomic<bool> stop_{false};
  const std::function<void(int)>* fn_ = nullptr;
  std::vector<std::thread> workers_;
};

}  // namespace gyrocomp::vmd_internal
