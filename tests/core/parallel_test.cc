#include "core/parallel.h"

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace hoof::core {
namespace {

TEST(ParallelTest, ResolveJobsKeepsAPositiveCountAndTakesEveryCoreForZero) {
  EXPECT_EQ(ResolveJobs(3), 3);
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  EXPECT_EQ(ResolveJobs(0), cores > 0 ? cores : 1);
  EXPECT_EQ(ResolveJobs(-2), ResolveJobs(0));
}

TEST(ParallelTest, EveryIndexRunsExactlyOnceWhateverTheThreadCount) {
  for (const int jobs : {1, 2, 3, 8, 0}) {
    for (const std::size_t n :
         {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{1000}}) {
      std::vector<std::atomic<int>> calls(n);
      ParallelFor(n, jobs, [&](std::size_t i) { ++calls[i]; });
      for (std::size_t i = 0; i < n; ++i)
        EXPECT_EQ(calls[i].load(), 1) << "jobs " << jobs << ", n " << n << ", i " << i;
    }
  }
}

TEST(ParallelTest, UsesSeveralThreadsTheCallerAmongThem) {
  // Each call waits until four threads have arrived: it can only finish if four run at once.
  std::atomic<int> arrived{0};
  std::vector<std::thread::id> who(4);
  ParallelFor(4, 4, [&](std::size_t i) {
    who[i] = std::this_thread::get_id();
    ++arrived;
    while (arrived.load() < 4) std::this_thread::yield();
  });
  int callers = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    callers += who[i] == std::this_thread::get_id();
    for (std::size_t j = 0; j < i; ++j) EXPECT_NE(who[i], who[j]);
  }
  EXPECT_EQ(callers, 1);
}

TEST(ParallelTest, TheFirstExceptionReachesTheCallerAndStopsFurtherIndices) {
  for (const int jobs : {1, 2, 4}) {
    std::atomic<int> started{0};
    try {
      ParallelFor(10000, jobs, [&](std::size_t i) {
        ++started;
        if (i == 5) throw std::runtime_error("trial 5 failed");
        std::this_thread::sleep_for(std::chrono::microseconds(100));  // 0.5 s for all, unstopped
      });
      ADD_FAILURE() << "no exception with " << jobs << " jobs";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), "trial 5 failed");
    }
    // The workers stop taking indices once one has thrown (each finishes the call it is in):
    // far fewer than the 10000 calls run.
    EXPECT_LT(started.load(), 100) << jobs << " jobs";
  }
}

}  // namespace
}  // namespace hoof::core
