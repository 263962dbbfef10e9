#include "fleetnav/planner/coordination/wait_cycles.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace fleetnav::planner {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;

TrafficClearanceDecision Decision(const std::string& robot, int cleared_up_to,
                                  std::vector<std::pair<std::string, int>> waits) {
  TrafficClearanceDecision d;
  d.robot_id = robot;
  d.cleared_up_to = cleared_up_to;
  for (const auto& [blocker, action] : waits)
    d.waits.push_back({robot, cleared_up_to + 1, blocker, action});
  return d;
}

TEST(WaitCyclesTest, AChainThatEndsInAFreeRobotIsNoCycle) {
  EXPECT_THAT(FindWaitCycles({Decision("a", -1, {{"b", 0}}), Decision("b", -1, {{"c", -1}}),
                              Decision("c", 2, {})}),
              IsEmpty());
}

TEST(WaitCyclesTest, WaitsThroughStandingRobotsCloseACircle) {
  // The dense hall's stall: a waits for b's next action, b for c standing, c's held job for a.
  const auto cycles =
      FindWaitCycles({Decision("x", 0, {}), Decision("a", 0, {{"b", 3}}),
                      Decision("b", 2, {{"c", -1}}), Decision("c", -1, {{"a", 5}})});
  ASSERT_EQ(cycles.size(), 1u);
  EXPECT_THAT(cycles[0], ElementsAre("a", "b", "c"));
}

TEST(WaitCyclesTest, AWaitForAnActionTheBlockerIsClearedForIsNoEdge) {
  // b is cleared through action 3, so it finishes it without a: a's wait will end.
  EXPECT_THAT(FindWaitCycles({Decision("a", 0, {{"b", 3}}), Decision("b", 3, {{"a", 1}})}),
              IsEmpty());
}

TEST(WaitCyclesTest, AParkedRobotClosesNoCircle) {
  // "p" has no decision: it stands without a job and can be sent aside.
  EXPECT_THAT(FindWaitCycles({Decision("a", -1, {{"p", -1}}), Decision("b", -1, {{"a", 0}})}),
              IsEmpty());
}

TEST(WaitCyclesTest, SeparateCirclesAreReportedApartInDecisionOrder) {
  const auto cycles = FindWaitCycles({Decision("d", -1, {{"e", -1}}), Decision("a", -1, {{"b", 0}}),
                                      Decision("e", -1, {{"d", 0}}), Decision("b", -1, {{"a", 0}}),
                                      Decision("f", -1, {{"a", 0}})});
  ASSERT_EQ(cycles.size(), 2u);
  EXPECT_THAT(cycles[0], ElementsAre("d", "e"));
  EXPECT_THAT(cycles[1], ElementsAre("a", "b"));
}

}  // namespace
}  // namespace fleetnav::planner
