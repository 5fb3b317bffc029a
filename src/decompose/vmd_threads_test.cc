// WorkerPool (vmd_threads.h): every round covers the work once, whatever the pool decides.
#include "vmd_threads.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <thread>
#include <vector>

namespace gyrocomp::vmd_internal {
namespace {

// Each round adds 1 to every item once: the items [n t / of, n (t + 1) / of) on thread t.
void RunRounds(WorkerPool& pool, std::vector<std::atomic<int>>& items, int rounds, const std::function<void(int)>& extra) {
  const std::size_t n = items.size();
  const std::function<void(int, int)> round = [&](int t, int of) {
    for (std::size_t i = n * t / of; i < n * (t + 1) / of; ++i) items[i].fetch_add(1, std::memory_order_relaxed);
    extra(t);
  };
  for (int r = 0; r < rounds; ++r) pool.Run(round);
}

TEST(WorkerPool, EveryRoundCoversEveryItemOnceForAnyThreadCount) {
  for (int threads : {1, 2, 3}) {
    SCOPED_TRACE(threads);
    std::vector<std::atomic<int>> items(1000);
    WorkerPool pool(threads);
    RunRounds(pool, items, 200, [](int) {});
    for (const auto& v : items) ASSERT_EQ(v.load(), 200);
  }
}

// A worker far slower than the caller makes every round on all threads a loss: after two the
// caller runs rounds alone (fn(0, 1), still every item once), trying all threads again later.
TEST(WorkerPool, RunsRoundsAloneWhenTheOtherThreadsMakeThemSlower) {
  std::vector<std::atomic<int>> items(64);
  WorkerPool pool(2);
  std::atomic<int> slow_calls{0};
  RunRounds(pool, items, 12, [&](int t) {
    if (t != 0) {
      slow_calls.fetch_add(1);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  for (const auto& v : items) ASSERT_EQ(v.load(), 12);
  EXPECT_EQ(pool.rounds_alone(), 10);  // rounds 1-2 on both threads (losses), 3-12 alone (16 due)
  EXPECT_EQ(slow_calls.load(), 2);
}

}  // namespace
}  // namespace gyrocomp::vmd_internal
