#include "fleetnav/server/traffic/planning_thread.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "absl/synchronization/notification.h"

namespace fleetnav::server {
namespace {

TEST(PlanningThreadTest, WithoutTheThreadATaskRunsAtOnceOnTheCallersThread) {
  PlanningThread searches;
  const std::thread::id caller = std::this_thread::get_id();
  std::thread::id ran_on;
  const uint64_t ticket = searches.Add([&] { ran_on = std::this_thread::get_id(); });
  EXPECT_FALSE(searches.threaded());
  EXPECT_TRUE(searches.Done(ticket));
  EXPECT_EQ(ran_on, caller);
}

TEST(PlanningThreadTest, OnTheThreadTasksRunInOrderAndAreDoneOnlyOnceTheyHaveRun) {
  PlanningThread searches;
  std::atomic<int> done_calls{0};
  searches.Start([&] { ++done_calls; });
  ASSERT_TRUE(searches.threaded());
  absl::Notification release;
  std::vector<int> order;  // written on the thread only, read after WaitForAll
  const uint64_t first = searches.Add([&] {
    release.WaitForNotification();
    order.push_back(1);
  });
  const uint64_t second = searches.Add([&] { order.push_back(2); });
  EXPECT_LT(first, second);
  // The first blocks the thread: neither is done.
  EXPECT_FALSE(searches.Done(first));
  EXPECT_FALSE(searches.Done(second));
  release.Notify();
  searches.WaitForAll();
  EXPECT_TRUE(searches.Done(first));
  EXPECT_TRUE(searches.Done(second));
  EXPECT_EQ(order, (std::vector<int>{1, 2}));
  searches.Stop();  // on_done is called after a task is done: joined, both calls were made
  EXPECT_EQ(done_calls.load(), 2);
  EXPECT_EQ(searches.task_cpu().count, 2);
}

TEST(PlanningThreadTest, StopDropsTasksNotBegunAndLaterTasksRunAtOnce) {
  PlanningThread searches;
  searches.Start({});
  absl::Notification started;
  absl::Notification release;
  searches.Add([&] {
    started.Notify();
    release.WaitForNotification();
  });
  bool dropped_ran = false;
  const uint64_t dropped = searches.Add([&] { dropped_ran = true; });
  started.WaitForNotification();
  std::thread stopper([&] { searches.Stop(); });
  // Stop has dropped the queue once the thread no longer takes tasks; then the first may end.
  while (searches.threaded()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  release.Notify();
  stopper.join();
  EXPECT_FALSE(dropped_ran);
  EXPECT_TRUE(searches.Done(dropped));  // nobody waits for it
  searches.WaitForAll();
  bool later_ran = false;
  searches.Add([&] { later_ran = true; });
  EXPECT_TRUE(later_ran);
}

}  // namespace
}  // namespace fleetnav::server
