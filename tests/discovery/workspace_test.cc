// The discovery workspace's parallel loop: an exception in a worker reaches the caller after
// every worker has stopped (one escaping a thread would be std::terminate).
#include <atomic>
#include <stdexcept>

#include <gtest/gtest.h>

#include "discovery/internal.h"

namespace hoof::discovery::internal {
namespace {

TEST(WorkspaceTest, AnExceptionInAWorkerReachesTheCaller) {
  Workspace ws;
  ws.threads = 4;
  std::atomic<int> done{0};
  EXPECT_THROW(ws.ParallelFor(1000,
                              [&](std::size_t i) {
                                if (i == 37) throw std::runtime_error("trial 37 failed");
                                ++done;
                              }),
               std::runtime_error);
  EXPECT_LT(done.load(), 1000);  // the others stopped early
  // And without one, every index runs once.
  std::atomic<long> sum{0};
  ws.ParallelFor(1000, [&](std::size_t i) { sum += static_cast<long>(i); });
  EXPECT_EQ(sum.load(), 999L * 1000 / 2);
}

}  // namespace
}  // namespace hoof::discovery::internal
