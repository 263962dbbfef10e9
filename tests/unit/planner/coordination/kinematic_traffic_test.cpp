#include "fleetnav/planner/coordination/kinematic_traffic.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/planner/coordination/traffic_dependencies.hpp"

namespace fleetnav::planner {
namespace {

using ::testing::HasSubstr;

OccupancyGrid Hall() {
  return *OccupancyGrid::Filled(400, 140, 0.05, Pose2(), OccupancyGrid::kFreeValue);  // 20 × 7 m
}

TEST(KinematicTrafficTest, OnlyFleetsWithADifferentialRobotAndAtMostTwelveUseIt) {
  EXPECT_TRUE(UseKinematicTraffic({LelyVectorModel(), MecanumPlatformModel()}));
  EXPECT_FALSE(UseKinematicTraffic({MecanumPlatformModel(), AckermannDeliveryModel()}));
  EXPECT_FALSE(UseKinematicTraffic(std::vector<RobotModel>(13, LelyVectorModel())));
}

TEST(KinematicTrafficTest, TwoRobotsSwapEndsOfAHallWithoutSharingACellAtOnce) {
  const std::vector<TrafficAgent> agents = {
      {"lely", "lely-vector", Pose2(3.0, 3.5, 0.0), Pose2(17.0, 3.5, 0.0)},
      {"omni", "mecanum-platform", Pose2(17.0, 3.5, kPi), Pose2(3.0, 3.5, kPi)}};
  const absl::StatusOr<TrafficPlan> plan = PlanKinematicTraffic(
      Hall(), agents, {LelyVectorModel(), MecanumPlatformModel()}, /*time_limit_s=*/5.0);
  ASSERT_TRUE(plan.ok()) << plan.status();
  EXPECT_EQ(plan->solver, "kinematic");
  ASSERT_EQ(plan->paths.size(), 2u);
  // Cells as wide as the smaller robot's circumscribed disc, a whole number of map cells.
  EXPECT_GE(plan->cell_size_m, 2.0 * MecanumPlatformModel().CircumscribedRadius() - 0.05);
  for (size_t i = 0; i < agents.size(); ++i) {
    const std::vector<PlannedPose>& path = plan->paths[i];
    EXPECT_TRUE(path.front().pose.translation().isApprox(agents[i].start.translation()));
    EXPECT_TRUE(path.back().pose.translation().isApprox(agents[i].goal.translation()));
    for (size_t t = 1; t + 1 < path.size(); ++t) {
      EXPECT_GT(path[t].t_s, path[t - 1].t_s);
      // One cell per step at most.
      EXPECT_LE((path[t].pose.translation() - path[t - 1].pose.translation()).norm(),
                plan->cell_size_m * std::sqrt(2.0) + 1e-9);
    }
  }
  // The robots meet head-on in the hall, so one must wait for the other somewhere.
  ASSERT_FALSE(plan->dependencies.empty());
  for (const TrafficDependency& d : plan->dependencies) {
    EXPECT_NE(d.from_robot_id, d.to_robot_id);
    EXPECT_TRUE(d.from_robot_id == "lely" || d.from_robot_id == "omni");
  }
  EXPECT_GE(plan->makespan_s, 14.0 / LelyVectorModel().limits.max_speed_mps);
}

TEST(KinematicTrafficTest, GoalsThatOverlapAreRefusedNamingTheAgent) {
  const std::vector<TrafficAgent> agents = {
      {"a", "lely-vector", Pose2(3.0, 3.5, 0.0), Pose2(10.0, 3.5, 0.0)},
      {"b", "lely-vector", Pose2(17.0, 3.5, kPi), Pose2(10.2, 3.5, kPi)}};
  const absl::StatusOr<TrafficPlan> plan =
      PlanKinematicTraffic(Hall(), agents, {LelyVectorModel(), LelyVectorModel()}, 5.0);
  EXPECT_EQ(plan.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(plan.status().message(), HasSubstr("agents[1].goal"));
  // A goal the robot cannot reach (behind a wall across the hall) is named the same way.
  OccupancyGrid walled = Hall();
  for (int y = 0; y < walled.height(); ++y) {
    for (int x = 238; x < 242; ++x) walled.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
  }
  const std::vector<TrafficAgent> behind = {
      {"a", "lely-vector", Pose2(3.0, 3.5, 0.0), Pose2(17.0, 3.5, 0.0)}};
  EXPECT_THAT(PlanKinematicTraffic(walled, behind, {LelyVectorModel()}, 5.0).status().message(),
              HasSubstr("agents[0].goal"));
}

TEST(TrafficDependenciesTest, CrossEdgesAreNamedByRobotAndActionIndex) {
  DependencyGraph graph(2);
  const int a0 = graph.AddAction(0), b0 = graph.AddAction(1), a1 = graph.AddAction(0);
  const int b1 = graph.AddAction(1);
  graph.AddCrossDependency(a1, b1);
  graph.AddCrossDependency(b0, a1);
  (void)a0;
  TrafficPlan plan;
  AppendDependencies(graph, {{"r0", "", {}, {}}, {"r1", "", {}, {}}}, &plan);
  ASSERT_EQ(plan.dependencies.size(), 2u);
  // In the order of the waiting action: a1 (waits for b0), then b1 (waits for a1).
  EXPECT_EQ(plan.dependencies[0].from_robot_id, "r1");
  EXPECT_EQ(plan.dependencies[0].from_action, 0);
  EXPECT_EQ(plan.dependencies[0].to_robot_id, "r0");
  EXPECT_EQ(plan.dependencies[0].to_action, 1);
  EXPECT_EQ(plan.dependencies[1].from_robot_id, "r0");
  EXPECT_EQ(plan.dependencies[1].from_action, 1);
  EXPECT_EQ(plan.dependencies[1].to_robot_id, "r1");
  EXPECT_EQ(plan.dependencies[1].to_action, 1);
}

}  // namespace
}  // namespace fleetnav::planner
