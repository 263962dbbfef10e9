#include "fleetnav/planner/coordination/dependency_graph.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace fleetnav::planner {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(DependencyGraphTest, ActionsKeepEachRobotsOrderAndTheirPlaceInIt) {
  DependencyGraph g(2);
  const int a0 = g.AddAction(0), b0 = g.AddAction(1), a1 = g.AddAction(0);
  EXPECT_EQ(g.num_actions(), 3);
  EXPECT_EQ(g.num_robots(), 2);
  EXPECT_THAT(g.ActionsOf(0), ElementsAre(a0, a1));
  EXPECT_THAT(g.ActionsOf(1), ElementsAre(b0));
  EXPECT_EQ(g.RobotOf(a1), 0);
  EXPECT_EQ(g.IndexInRobot(a1), 1);
  EXPECT_EQ(g.IndexInRobot(b0), 0);
  // a1 waits for a0 (its robot's previous action) without a stored edge.
  EXPECT_THAT(g.DependenciesOf(a1), ElementsAre(a0));
  EXPECT_TRUE(g.DependenciesOf(a0).empty());
}

TEST(DependencyGraphTest, CrossDependenciesAreStoredOnceAndOnlyAcrossRobots) {
  DependencyGraph g(2);
  const int a0 = g.AddAction(0), a1 = g.AddAction(0), b0 = g.AddAction(1);
  EXPECT_TRUE(g.AddCrossDependency(a0, b0));
  EXPECT_FALSE(g.AddCrossDependency(a0, b0));  // twice
  EXPECT_FALSE(g.AddCrossDependency(a0, a1));  // same robot: implied by the order
  EXPECT_EQ(g.num_cross_dependencies(), 1);
  EXPECT_THAT(g.CrossDependenciesOf(b0), ElementsAre(a0));
  EXPECT_THAT(g.DependenciesOf(a1), ElementsAre(a0));
  EXPECT_TRUE(g.CheckAcyclic().ok());
}

TEST(DependencyGraphTest, RobotsWaitingForEachOtherAreACycleNamingThem) {
  // Robot 0's second action waits for robot 1's first, which waits for robot 0's second.
  DependencyGraph g(2);
  g.AddAction(0);
  const int a1 = g.AddAction(0), b0 = g.AddAction(1), b1 = g.AddAction(1);
  g.AddCrossDependency(b0, a1);
  EXPECT_TRUE(g.CheckAcyclic().ok());
  g.AddCrossDependency(a1, b0);
  const absl::Status cycle = g.CheckAcyclic();
  EXPECT_EQ(cycle.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(std::string(cycle.message()), HasSubstr("robots"));
  (void)b1;
}

}  // namespace
}  // namespace fleetnav::planner
