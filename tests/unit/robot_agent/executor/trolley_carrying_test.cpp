// Carrying a trolley in the agent: a route may undock only what a trolley dock before it
// latched; while carrying, free navigation plans with the grown footprint; the undock lowers the
// lift and waits for it; the executor keeps what is on the lift across actions; the laser
// drops the carried trolley's own legs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/robot_agent/control/modes/undock_controller.hpp"
#include "fleetnav/robot_agent/laser_filters.hpp"
#include "fleetnav/robot_agent/mode_factory.hpp"
#include "fleetnav/robot_agent/route_executor.hpp"

namespace fleetnav::agent {
namespace {

RouteAction DockTrolley() {
  return RouteAction{DockAction{DockTarget::kTrolley, "t1"}, {EndConditionKind::kGoalReached, 0}};
}
RouteAction Undock() { return RouteAction{UndockAction{}, {}}; }

bool Says(const absl::Status& status, const std::string& text) {
  return status.message().find(text) != std::string::npos;
}

TEST(TrolleyCarryingTest, UndockFollowsATrolleyDockAndADockNeedsAnEmptyLift) {
  const RouteContext omni{MecanumPlatformModel(), std::nullopt, nullptr};
  Route route{"r", "m", {Undock()}};
  absl::Status s = CheckRoute(route, omni);
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_TRUE(Says(s, "actions[0] (undock): the robot carries no trolley here")) << s;

  route.actions = {DockTrolley(), Undock()};
  EXPECT_TRUE(CheckRoute(route, omni).ok()) << CheckRoute(route, omni);

  route.actions = {DockTrolley(), DockTrolley()};
  s = CheckRoute(route, omni);
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_TRUE(Says(s, "actions[1] (dock): the robot already carries a trolley")) << s;

  // A robot that starts a route carrying (an earlier route docked) may undock at once.
  RouteContext carrying = omni;
  carrying.carried_load_m = Eigen::Vector2d(1.0, 0.7);
  route.actions = {Undock()};
  EXPECT_TRUE(CheckRoute(route, carrying).ok());

  const RouteContext car{AckermannDeliveryModel(), std::nullopt, nullptr};
  s = CheckRoute(route, car);
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_TRUE(Says(s, "ackermann-delivery has no lift")) << s;
}

// A 6 x 4 m room: a goal 0.3 m from its south wall leaves room for the platform (0.24 m half
// width) but not for the trolley it carries (0.35 m).
TEST(TrolleyCarryingTest, FreeNavigationWhileCarryingJudgesGoalsWithTheTrolley) {
  OccupancyGrid grid =
      OccupancyGrid::Filled(60, 40, 0.1, Pose2(), OccupancyGrid::kFreeValue).value();
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 60; ++x) {
      if (x == 0 || y == 0 || x == 59 || y == 39)
        grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
    }
  }
  RouteContext omni{MecanumPlatformModel(), std::nullopt,
                    std::make_shared<const OccupancyGrid>(std::move(grid))};
  FreeNavigationAction near_wall;
  near_wall.goal = Pose2(3.0, 0.1 + 0.3, 0.0);
  const RouteAction nav{near_wall, {EndConditionKind::kGoalReached, 0}};
  ModeParams params;
  params.free_navigation.padding_m = 0.02;
  Route route{"r", "m", {nav}};
  EXPECT_TRUE(CheckRoute(route, omni, params).ok()) << CheckRoute(route, omni, params);
  route.actions = {DockTrolley(), nav};
  const absl::Status s = CheckRoute(route, omni, params);
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_TRUE(Says(s, "actions[1] (free_navigation)")) << s;
  EXPECT_TRUE(Says(s, "with the trolley it carries")) << s;
  // Set down first, the platform fits again.
  route.actions = {DockTrolley(), Undock(), nav};
  EXPECT_TRUE(CheckRoute(route, omni, params).ok()) << CheckRoute(route, omni, params);
}

ControlInput WithLift(bool loaded) {
  ControlInput input;
  input.dt_s = 0.02;
  input.perception.lift_loaded = loaded;
  return input;
}

TEST(TrolleyCarryingTest, UndockLowersTheLiftAndWaitsUntilItIsEmpty) {
  UndockController undock(1.0);
  ControlOutput out = undock.Step(WithLift(true));
  ASSERT_TRUE(out.lift_raised.has_value());
  EXPECT_FALSE(*out.lift_raised);
  EXPECT_FALSE(out.done);
  EXPECT_EQ(out.command.vx_mps, 0.0);
  out = undock.Step(WithLift(false));
  EXPECT_TRUE(out.done);

  // A lift that keeps its load fails the action with the reason.
  UndockController stuck(1.0);
  for (int i = 0; i < 60 && stuck.Step(WithLift(true)).failure.ok(); ++i) {
  }
  const absl::Status failed = stuck.Step(WithLift(true)).failure;
  EXPECT_EQ(failed.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_TRUE(Says(failed, "still carries a load")) << failed;
}

TEST(TrolleyCarryingTest, TheExecutorKeepsTheLoadUntilTheUndockSetsItDown) {
  RouteContext carrying{MecanumPlatformModel(), std::nullopt, nullptr};
  carrying.carried_load_m = Eigen::Vector2d(1.0, 0.7);
  Route route{"r", "m", {Undock(), RouteAction{MoveAction{-1.2, 0.0, 0.15}, {}}}};
  RouteExecutor executor(route, carrying);
  ExecutorOutput out = executor.Step(WithLift(true));
  ASSERT_EQ(executor.state(), ExecutionState::kRunning) << executor.failure();
  EXPECT_EQ(out.action_index, 0);
  EXPECT_FALSE(out.lift_raised);  // lowering
  EXPECT_TRUE(out.carried_load_m.has_value());
  out = executor.Step(WithLift(false));
  EXPECT_EQ(out.action_index, 1);  // on to the move
  EXPECT_FALSE(out.lift_raised);
  EXPECT_FALSE(out.carried_load_m.has_value());
}

// The platform's laser (0.35 m ahead of its centre) sees the carried trolley's front legs at
// its corners; those returns are dropped, a wall 2 m ahead is kept.
TEST(TrolleyCarryingTest, TheLaserDropsTheCarriedTrolleysLegs) {
  const Pose2 laser_in_base(0.35, 0.0, 0.0);
  LaserScanSample scan;
  scan.name = "laser";
  scan.angle_min_rad = -(kPi / 2);
  scan.angle_increment_rad = kPi / 180.0;
  scan.range_max_m = 10.0;
  scan.ranges_m.assign(181, 2.0f);
  const auto beam_at = [&](const Eigen::Vector2d& p_in_base) {
    const Eigen::Vector2d p = laser_in_base.Inverse().TransformPoint(p_in_base);
    const int i =
        static_cast<int>(std::lround((std::atan2(p.y(), p.x()) + (kPi / 2)) * 180.0 / kPi));
    scan.ranges_m[static_cast<size_t>(i)] = static_cast<float>(p.norm());
    return static_cast<size_t>(i);
  };
  const size_t left = beam_at({0.475, 0.325});
  const size_t right = beam_at({0.475, -0.325});
  const Eigen::AlignedBox2d load(Eigen::Vector2d(-0.55, -0.4), Eigen::Vector2d(0.55, 0.4));
  EXPECT_EQ(MaskCarriedLoad(load, laser_in_base, &scan), 2);
  EXPECT_TRUE(std::isnan(scan.ranges_m[left]));
  EXPECT_TRUE(std::isnan(scan.ranges_m[right]));
  EXPECT_EQ(scan.ranges_m[90], 2.0f);
}

}  // namespace
}  // namespace fleetnav::agent
