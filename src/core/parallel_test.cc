// ParallelFor (include/gyrocomp/core/parallel.h): every item once, on any thread count; the
// exception of the lowest failing item reaches the caller after every thread has finished.
#include "gyrocomp/core/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

namespace gyrocomp {
namespace {

TEST(ParallelFor, EveryItemExactlyOnceForAnyThreadCount) {
  for (int threads : {0, 1, 2, 3, 8}) {
    for (std::size_t n : {0u, 1u, 2u, 7u, 100u}) {
      std::vector<std::atomic<int>> calls(n);
      ParallelFor(n, threads, [&](std::size_t i) { calls[i].fetch_add(1); });
      for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(calls[i].load(), 1) << "threads " << threads << " n " << n << " item " << i;
    }
  }
}

TEST(ParallelFor, TheLowestFailingItemsExceptionIsRethrown) {
  // Items 3 and 5 throw; whichever thread meets which first, the caller sees item 3's.
  for (int threads : {1, 2, 4}) {
    try {
      ParallelFor(10, threads, [](std::size_t i) {
        if (i == 3 || i == 5) throw std::runtime_error("item " + std::to_string(i));
      });
      FAIL() << "no exception with " << threads << " threads";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 3") << threads << " threads";
    }
  }
}

TEST(ParallelFor, AFailureStopsHandingOutItems) {
  std::atomic<int> ran{0};
  EXPECT_THROW(ParallelFor(1000, 1,
                           [&](std::size_t i) {
                             ran.fetch_add(1);
                             if (i == 0) throw std::runtime_error("first");
                           }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 1);
}

TEST(ParallelFor, DefaultItemThreadsIsBetweenOneAndTheCap) {
  EXPECT_GE(DefaultItemThreads(), 1);
  EXPECT_LE(DefaultItemThreads(), 2);
  EXPECT_EQ(DefaultItemThreads(1), 1);
}

}  // namespace
}  // namespace gyrocomp
