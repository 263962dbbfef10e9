#include "fleetnav/core/clock.hpp"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace fleetnav {
namespace {

TEST(SystemClockTest, IsMonotonic) {
  const SystemClock clock;
  int64_t previous = clock.NowNs();
  for (int i = 0; i < 1000; ++i) {
    const int64_t now = clock.NowNs();
    EXPECT_GE(now, previous);
    previous = now;
  }
  EXPECT_GT(clock.NowS(), 0.0);
}

TEST(ManualClockTest, StartsWhereToldAndAdvances) {
  ManualClock clock(1'000);
  EXPECT_EQ(clock.NowNs(), 1'000);
  clock.AdvanceNs(500);
  EXPECT_EQ(clock.NowNs(), 1'500);
  clock.SetNs(2'000'000'000);
  EXPECT_EQ(clock.NowNs(), 2'000'000'000);
  EXPECT_DOUBLE_EQ(clock.NowS(), 2.0);
}

TEST(ManualClockTest, NeverGoesBackwards) {
  ManualClock clock(5'000);
  clock.SetNs(4'000);
  EXPECT_EQ(clock.NowNs(), 5'000);
  clock.AdvanceNs(-100);
  EXPECT_EQ(clock.NowNs(), 5'000);
  clock.SetNs(5'000);
  EXPECT_EQ(clock.NowNs(), 5'000);
}

TEST(ManualClockTest, ItsCalendarIsTheZeroSetPlusTheTime) {
  ManualClock clock(2'500'000'000, 1'000'000);
  EXPECT_EQ(clock.UnixMs(), 1'002'500);
  clock.SetUnixMsAtZero(1'700'000'000'000);  // a simulation's calendar start
  EXPECT_EQ(clock.UnixMs(), 1'700'000'002'500);
  EXPECT_EQ(clock.NowNs(), 2'500'000'000);
}

TEST(ManualClockTest, IsUsableThroughTheInterface) {
  ManualClock manual;
  const Clock& clock = manual;
  manual.AdvanceNs(250'000'000);
  EXPECT_DOUBLE_EQ(clock.NowS(), 0.25);
}

TEST(ManualClockTest, ConcurrentAdvancesAreNotLost) {
  ManualClock clock;
  constexpr int kThreads = 4;
  constexpr int kSteps = 5000;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&clock] {
      for (int i = 0; i < kSteps; ++i) {
        clock.AdvanceNs(1);
        (void)clock.NowNs();
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(clock.NowNs(), kThreads * kSteps);
}

}  // namespace
}  // namespace fleetnav
