// Independent items on a few threads: the axes of an IMU's Allan analysis, the VMD modes whose
// sample entropy the classifier measures. Each item is computed by one thread, whole, exactly as
// it would be alone, so the results are the same bits for any thread count.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>

namespace gyrocomp {

// The default thread count of the stages that parallelise over items: the machine's hardware
// threads, at most `cap` (2: the reference machine has two, and more threads each holding a
// full-length work array cost memory for little gain), at least 1.
inline int DefaultItemThreads(int cap = 2) {
  return std::max(1, std::min(cap, static_cast<int>(std::thread::hardware_concurrency())));
}

// Calls fn(i) for every i in [0, n) on min(threads, n) threads, the caller being one of them;
// items are handed out in index order from a shared counter. An exception from fn stops the
// handing out of further items; once every thread has finished, the exception of the lowest
// item index that threw is rethrown on the caller (a Cancelled, a bad_alloc).
template <class Fn>
void ParallelFor(std::size_t n, int threads, Fn&& fn) {
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::vector<std::exception_ptr> errors(n);
  auto worker = [&] {
    for (std::size_t i; !failed.load(std::memory_order_relaxed) && (i = next.fetch_add(1)) < n;) {
      try {
        fn(i);
      } catch (...) {
        errors[i] = std::current_exception();
        failed.store(true, std::memory_order_relaxed);
      }
    }
  };
  const std::size_t workers = std::min<std::size_t>(n, static_cast<std::size_t>(std::max(1, threads)));
  std::vector<std::thread> pool;
  try {
    for (std::size_t t = 1; t < workers; ++t) pool.emplace_back(worker);
  } catch (const std::system_error&) {
    // No more threads from the system: the caller and the threads started do all the items.
  }
  worker();
  for (std::thread& th : pool) th.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace gyrocomp
