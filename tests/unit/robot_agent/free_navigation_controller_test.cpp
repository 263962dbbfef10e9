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

/// A perfect omnidirectional platform: the body twist integrated in small steps.
class KinematicOmni {
 public:
  explicit KinematicOmni(const Pose2& start) : pose_(start) {}
  void Step(const Twist2& twist, double dt_s) {
    constexpr int kSub = 10;
    double x = pose_.x_m(), y = pose_.y_m(), yaw = pose_.yaw_rad();
    for (int i = 0; i < kSub; ++i) {
      const double h = dt_s / kSub;
      const double mid = yaw + 0.5 * twist.yaw_rate_radps * h;
      x += h * (std::cos(mid) * twist.vx_mps - std::sin(mid) * twist.vy_mps);
      y += h * (std::sin(mid) * twist.vx_mps + std::cos(mid) * twist.vy_mps);
      yaw += twist.yaw_rate_radps * h;
    }
    pose_ = Pose2(x, y, yaw);
  }
  Pose2 pose() const { return pose_; }

 private:
  Pose2 pose_;
};

// The mecanum platform through the door: the lattice path is spline-smoothed and tracked
// holonomically; the footprint never touches the wall, the limits hold, the goal pose is
// reached within the tracker's tolerances.
TEST(FreeNavigationControllerTest, AnOmniPlatformReachesTheGoalPoseWithoutTouchingTheWall) {
  const RobotModel omni = MecanumPlatformModel();
  const std::shared_ptr<const OccupancyGrid> map = DoorMap();
  planner::CostmapParams exact;
  exact.padding_m = 0.0;
  planner::Costmap walls = planner::Costmap::Build(*map, omni.footprint_m, exact).value();
  for (const Pose2 goal : {Pose2(19.0, 4.0, DegToRad(-90)), Pose2(19.0, 12.0, DegToRad(45))}) {
    FreeNavigationAction action;
    action.goal = goal;
    action.speed_mps = 0.4;
    FreeNavigationController controller(action, omni, map, FreeNavigationParams{});
    KinematicOmni robot(Pose2(4.0, 12.0, DegToRad(90)));
    Twist2 last;
    bool done = false;
    bool moved_sideways = false;
    int step = 0;
    for (; step < 30000 && !done; ++step) {
      const ControlOutput out = controller.Step(OdometryInput(robot.pose(), kDt));
      ASSERT_TRUE(out.failure.ok()) << out.failure;
      done = out.done;
      const Twist2& c = out.command;
      ASSERT_LE(std::hypot(c.vx_mps, c.vy_mps), omni.limits.max_speed_mps + 1e-9);
      ASSERT_LE(std::abs(c.vy_mps), omni.limits.max_lateral_speed_mps + 1e-9);
      ASSERT_LE(std::abs(c.yaw_rate_radps), omni.limits.max_yaw_rate_radps + 1e-9);
      ASSERT_LE(std::hypot(c.vx_mps - last.vx_mps, c.vy_mps - last.vy_mps),
                omni.limits.max_accel_mps2 * kDt + 1e-9);
      moved_sideways = moved_sideways || std::abs(c.vy_mps) > 0.1;
      last = c;
      robot.Step(c, kDt);
      const Pose2 p = robot.pose();
      ASSERT_TRUE(walls.PoseFree(p.x_m(), p.y_m(), p.yaw_rad()))
          << "step " << step << " at " << p.DebugString();
    }
    ASSERT_TRUE(done) << robot.pose().DebugString();
    const HolonomicTrackerParams tolerances;
    EXPECT_TRUE(robot.pose().IsNear(goal, tolerances.goal_tolerance_m + 0.01,
                                    tolerances.goal_tolerance_rad + 0.01))
        << robot.pose().DebugString();
    EXPECT_TRUE(moved_sideways);  // it used its lateral axis
  }
}

/// A perfect car: the bicycle model about the rear axle, steering = atan(ω L / v) within the
/// lock, as the simulator turns a twist into a steering angle.
class KinematicCar {
 public:
  KinematicCar(const Pose2& start, const RobotModel& model) : pose_(start), model_(model) {}
  void Step(const Twist2& twist, double dt_s) {
    const double v = twist.vx_mps;
    if (std::abs(v) > 1e-3) {
      steering_rad_ = std::clamp(std::atan(twist.yaw_rate_radps * model_.wheelbase_m / v),
                                 -model_.limits.max_steering_rad, model_.limits.max_steering_rad);
    }
    const double w = v * std::tan(steering_rad_) / model_.wheelbase_m;
    KinematicOmni body(pose_);
    body.Step(Twist2{v, 0.0, w}, dt_s);
    pose_ = body.pose();
  }
  Pose2 pose() const { return pose_; }

 private:
  Pose2 pose_;
  RobotModel model_;
  double steering_rad_ = 0.0;
};

// The Ackermann robot through the door to goals whose yaw no lattice heading reaches: a
// Reeds-Shepp path, tracked with pure pursuit (reversing where the path has cusps); it never
// turns in place, keeps its limits and ends near the goal pose without touching the wall.
TEST(FreeNavigationControllerTest, AnAckermannRobotReachesTheGoalWithoutTurningInPlace) {
  const RobotModel car = AckermannDeliveryModel();
  const std::shared_ptr<const OccupancyGrid> map = DoorMap();
  planner::CostmapParams exact;
  exact.padding_m = 0.0;
  planner::Costmap walls = planner::Costmap::Build(*map, car.footprint_m, exact).value();
  for (const Pose2 goal : {Pose2(19.0, 4.0, DegToRad(-100)), Pose2(17.0, 12.0, DegToRad(170))}) {
    FreeNavigationAction action;
    action.goal = goal;
    action.speed_mps = 0.6;
    FreeNavigationController controller(action, car, map, FreeNavigationParams{});
    KinematicCar robot(Pose2(4.0, 12.0, 0.0), car);
    bool done = false;
    for (int step = 0; step < 30000 && !done; ++step) {
      const ControlOutput out = controller.Step(OdometryInput(robot.pose(), kDt));
      ASSERT_TRUE(out.failure.ok()) << out.failure;
      done = out.done;
      const Twist2& c = out.command;
      ASSERT_EQ(c.vy_mps, 0.0);
      ASSERT_LE(c.vx_mps, car.limits.max_speed_mps + 1e-9);
      ASSERT_GE(c.vx_mps, -car.limits.max_reverse_speed_mps - 1e-9);
      if (std::abs(c.vx_mps) < 1e-6) {
        ASSERT_EQ(c.yaw_rate_radps, 0.0) << "turned in place";
      }
      robot.Step(c, kDt);
      const Pose2 p = robot.pose();
      ASSERT_TRUE(walls.PoseFree(p.x_m(), p.y_m(), p.yaw_rad()))
          << "step " << step << " at " << p.DebugString();
    }
    ASSERT_TRUE(done) << robot.pose().DebugString();
    EXPECT_TRUE(robot.pose().IsNear(goal, 0.15, DegToRad(8))) << robot.pose().DebugString();
  }
}

}  // namespace
}  // namespace fleetnav::agent
