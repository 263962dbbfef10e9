#include "fleetnav/proto/traffic_plan_convert.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "fleetnav/core/angles.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

TEST(TrafficPlanConvertTest, MapInfoKeepsEveryField) {
  MapInfo info{"barn", 3, 640, 480, 0.05, "after the fence moved", 1'795'564'812'500};
  const v1::MapInfo wire = ToProto(info);
  EXPECT_EQ(wire.map_id(), "barn");
  EXPECT_EQ(wire.version(), 3u);
  EXPECT_EQ(wire.width(), 640u);
  EXPECT_EQ(wire.height(), 480u);
  EXPECT_DOUBLE_EQ(wire.resolution_m(), 0.05);
  EXPECT_EQ(wire.description(), "after the fence moved");
  EXPECT_EQ(wire.created_unix_ms(), 1'795'564'812'500);
}

TEST(TrafficPlanConvertTest, AnAgentComesInWithItsPoses) {
  v1::PlanPathsRequest::Agent wire;
  wire.set_robot_id("lely1");
  wire.set_kind_name("lely_vector");
  wire.mutable_start()->set_x_m(1.0);
  wire.mutable_start()->set_y_m(2.0);
  wire.mutable_goal()->set_x_m(5.0);
  wire.mutable_goal()->set_yaw_rad(kPi / 2);
  absl::StatusOr<TrafficAgent> agent = FromProto(wire, "agents[0]");
  ASSERT_TRUE(agent.ok()) << agent.status();
  EXPECT_EQ(agent->robot_id, "lely1");
  EXPECT_EQ(agent->kind_name, "lely_vector");
  EXPECT_DOUBLE_EQ(agent->start.x_m(), 1.0);
  EXPECT_DOUBLE_EQ(agent->start.y_m(), 2.0);
  EXPECT_DOUBLE_EQ(agent->goal.x_m(), 5.0);
  EXPECT_NEAR(agent->goal.yaw_rad(), kPi / 2, 1e-12);
}

TEST(TrafficPlanConvertTest, ANonFiniteGoalIsRefusedNamingTheField) {
  v1::PlanPathsRequest::Agent wire;
  wire.set_robot_id("lely1");
  wire.mutable_goal()->set_x_m(std::nan(""));
  absl::StatusOr<TrafficAgent> agent = FromProto(wire, "agents[2]");
  ASSERT_EQ(agent.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(agent.status().message(), HasSubstr("agents[2].goal"));
}

TEST(TrafficPlanConvertTest, APlanGoesOutInTheOrderOfItsAgents) {
  const std::vector<TrafficAgent> agents = {{"a", "omni_store", Pose2(), Pose2(1, 0, 0)},
                                            {"b", "omni_store", Pose2(1, 0, 0), Pose2()}};
  TrafficPlan plan;
  plan.paths = {{{0.0, Pose2()}, {2.0, Pose2(1, 0, 0)}}, {{0.0, Pose2(1, 0, 0)}}};
  plan.waits_beside_goal = {false, true};
  plan.dependencies = {{"a", 1, "b", 0}};
  plan.sum_of_costs_s = 2.0;
  plan.makespan_s = 2.0;
  plan.planning_ms = 0.4;
  plan.cell_size_m = 0.8;
  plan.solver = "eecbs";
  const v1::PlanPathsResponse wire = ToProto(plan, agents);
  ASSERT_EQ(wire.paths_size(), 2);
  EXPECT_EQ(wire.paths(0).robot_id(), "a");
  EXPECT_FALSE(wire.paths(0).waits_beside_goal());
  ASSERT_EQ(wire.paths(0).poses_size(), 2);
  EXPECT_DOUBLE_EQ(wire.paths(0).poses(1).t_s(), 2.0);
  EXPECT_DOUBLE_EQ(wire.paths(0).poses(1).pose().x_m(), 1.0);
  EXPECT_EQ(wire.paths(1).robot_id(), "b");
  EXPECT_TRUE(wire.paths(1).waits_beside_goal());
  ASSERT_EQ(wire.dependencies_size(), 1);
  EXPECT_EQ(wire.dependencies(0).from_robot_id(), "a");
  EXPECT_EQ(wire.dependencies(0).from_action(), 1u);
  EXPECT_EQ(wire.dependencies(0).to_robot_id(), "b");
  EXPECT_EQ(wire.dependencies(0).to_action(), 0u);
  EXPECT_DOUBLE_EQ(wire.sum_of_costs_s(), 2.0);
  EXPECT_DOUBLE_EQ(wire.makespan_s(), 2.0);
  EXPECT_DOUBLE_EQ(wire.planning_ms(), 0.4);
  EXPECT_DOUBLE_EQ(wire.cell_size_m(), 0.8);
  EXPECT_EQ(wire.solver(), "eecbs");
}

}  // namespace
}  // namespace fleetnav
