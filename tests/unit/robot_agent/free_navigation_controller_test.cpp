// Free navigation closed around a perfect unicycle on a map with a wall and a door: plan with
// the lattice planner for the Lely (no reversing), track with regulated pure pursuit.
#include "fleetnav/robot_agent/free_navigation_controller.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "fleetnav/core/angles.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

using ::testing::HasSubstr;
using testing::KinematicUnicycle;

constexpr double kDt = 0.02;

/// 24 m × 16 m at 0.1 m: a border and a wall at x = 12 m with a 4 m door (y 6–10 m).
std::shared_ptr<const OccupancyGrid> DoorMap() {
  OccupancyGrid grid =
      OccupancyGrid::Filled(240, 160, 0.1, Pose2(), OccupancyGrid::kFreeValue).value();
  for (int y = 0; y < 160; ++y) {
    for (int x = 0; x < 240; ++x) {
      const bool border = x < 2 || y < 2 || x >= 238 || y >= 158;
      const bool wall = x >= 118 && x < 122 && !(y >= 60 && y < 100);
      if (border || wall) grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
    }
  }
  return std::make_shared<const OccupancyGrid>(std::move(grid));
}

struct NavRun {
  bool done = false;
  absl::Status failure;
  Pose2 end;
  double min_wall_clearance_m = 1e9;
};

NavRun Drive(const FreeNavigationAction& action, const Pose2& start) {
  const RobotModel lely = LelyVectorModel();
  FreeNavigationController controller(action, lely, DoorMap(), FreeNavigationParams{});
  KinematicUnicycle robot(start);
  NavRun run;
  for (int step = 0; step < 30000; ++step) {
    const ControlOutput out = controller.Step(OdometryInput(robot.pose(), kDt));
    EXPECT_EQ(out.mode, NavigationMode::kFreeNavigation);
    if (!out.failure.ok()) {
      run.failure = out.failure;
      break;
    }
    if (out.done) {
      run.done = true;
      break;
    }
    EXPECT_GE(out.command.vx_mps, 0.0) << "the Lely never reverses";
    EXPECT_LE(out.command.vx_mps, lely.limits.max_speed_mps + 1e-9);
    EXPECT_LE(std::abs(out.command.yaw_rate_radps), lely.limits.max_yaw_rate_radps + 1e-9);
    robot.Step(out.command, kDt);
  }
  run.end = robot.pose();
  return run;
}

TEST(FreeNavigationControllerTest, ThroughTheDoorToTheGoalPose) {
  FreeNavigationAction action;
  action.goal = Pose2(19.0, 4.0, DegToRad(-90));
  action.speed_mps = 0.4;
  const NavRun run = Drive(action, Pose2(4.0, 12.0, 0.0));
  ASSERT_TRUE(run.failure.ok()) << run.failure;
  ASSERT_TRUE(run.done);
  EXPECT_TRUE(run.end.IsNear(action.goal, 0.15, DegToRad(3))) << run.end.DebugString();
}

TEST(FreeNavigationControllerTest, PassesTheWaypoints) {
  FreeNavigationAction action;
  action.waypoints_m = {Eigen::Vector2d(6.0, 4.0)};
  action.goal = Pose2(19.0, 12.0, 0.0);
  action.speed_mps = 0.4;
  const NavRun run = Drive(action, Pose2(4.0, 12.0, 0.0));
  ASSERT_TRUE(run.failure.ok()) << run.failure;
  ASSERT_TRUE(run.done);
  EXPECT_TRUE(run.end.IsNear(action.goal, 0.15, DegToRad(3))) << run.end.DebugString();
}

TEST(FreeNavigationControllerTest, GoalInAWallIsRefusedBeforeMoving) {
  FreeNavigationAction action;
  action.goal = Pose2(12.0, 2.5, 0.0);
  const absl::Status status =
      CheckFreeNavigation(action, LelyVectorModel(), *DoorMap(), /*padding_m=*/0.1);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(status.message()), HasSubstr("goal (12.00, 2.50)"));
}

TEST(FreeNavigationControllerTest, UnreachableGoalFailsWithTheReason) {
  // A closed wall: the door is filled.
  OccupancyGrid grid = *DoorMap();
  for (int y = 60; y < 100; ++y) {
    for (int x = 118; x < 122; ++x) grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
  }
  FreeNavigationAction action;
  action.goal = Pose2(19.0, 8.0, 0.0);
  FreeNavigationController controller(action, LelyVectorModel(),
                                      std::make_shared<const OccupancyGrid>(grid),
                                      FreeNavigationParams{});
  const ControlOutput out = controller.Step(OdometryInput(Pose2(4.0, 8.0, 0.0), kDt));
  EXPECT_FALSE(out.failure.ok());
  EXPECT_THAT(std::string(out.failure.message()), HasSubstr("cannot be reached"));
}

}  // namespace
}  // namespace fleetnav::agent
