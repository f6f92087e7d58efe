#include "engine/core/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace ivgi {
namespace {

TEST(Parallel, CallsEveryIndexOnceWhateverTheThreads) {
  for (unsigned threads : {0u, 1u, 2u, 7u, 64u}) {
    std::vector<std::atomic<int>> calls(1000);
    parallelFor(
        calls.size(), [&](size_t i) { calls[i].fetch_add(1); }, threads);
    for (size_t i = 0; i < calls.size(); ++i) ASSERT_EQ(calls[i].load(), 1) << "index " << i << ", threads " << threads;
  }
  bool called = false;
  parallelFor(0, [&](size_t) { called = true; });
  EXPECT_FALSE(called);
}

TEST(Parallel, AnErrorReachesTheCallerAndStopsTheRest) {
  std::atomic<size_t> calls{0};
  EXPECT_THROW(parallelFor(
                   2000,
                   [&](size_t i) {
                     calls.fetch_add(1);
                     if (i == 10) throw std::runtime_error("index 10");
                     std::this_thread::sleep_for(std::chrono::milliseconds(1));
                   },
                   4),
               std::runtime_error);
  // The threads stop taking indices once one has failed: far fewer than all were called.
  EXPECT_LT(calls.load(), 1000u);
}

}  // namespace
}  // namespace ivgi
