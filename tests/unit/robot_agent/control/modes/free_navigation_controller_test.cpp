// Free navigation closed around a perfect unicycle on a map with a wall and a door: plan with
// the lattice planner for the Lely (no reversing), track with regulated pure pursuit.
#include "fleetnav/robot_agent/control/modes/free_navigation_controller.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

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

// The holonomic tracker at the goal's place with the closest path pose a little before the end,
// at another yaw (a spline's last piece): it turns onto the goal's yaw and ends, instead of
// holding the closest pose's yaw for ever.
TEST(HolonomicTrackerTest, AtTheGoalsPlaceItTurnsOntoTheGoalsYawAndEnds) {
  const RobotModel omni = MecanumPlatformModel();
  HolonomicTracker tracker(HolonomicTrackerParams{}, omni.limits);
  std::vector<Pose2> path;
  for (int i = 0; i <= 20; ++i) path.emplace_back(0.05 * i, 0.0, 0.0);
  const Pose2 goal(1.02, 0.0, 0.8);
  path.push_back(goal);
  tracker.SetPath(path);
  KinematicOmni robot(Pose2(0.0, 0.0, 0.0));
  int step = 0;
  for (; step < 20000 && !tracker.done(); ++step) robot.Step(tracker.Step(robot.pose(), kDt), kDt);
  ASSERT_TRUE(tracker.done()) << robot.pose().DebugString();
  const HolonomicTrackerParams tolerances;
  EXPECT_TRUE(robot.pose().IsNear(goal, tolerances.goal_tolerance_m + 0.01,
                                  tolerances.goal_tolerance_rad + 0.01))
      << robot.pose().DebugString();
}

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

// A trolley lifted off in a 1 m door of a closed wall: the map still shows it there, blocking
// the only way. Told where it was lifted from, the platform plans through the door and drives
// to the goal; not told, the goal is unreachable.
TEST(FreeNavigationControllerTest, AMapsCopyOfALiftedTrolleyIsLeftOffThePlan) {
  OccupancyGrid grid = *DoorMap();
  for (int y = 60; y < 100; ++y) {
    const bool door = y >= 75 && y < 85;
    const bool trolley_block = y >= 77 && y < 83;
    for (int x = 112; x < 128; ++x) {
      const bool wall = x >= 118 && x < 122;
      if ((wall && !door) || (trolley_block && x >= 116 && x < 124)) {
        grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
      }
    }
  }
  const auto map = std::make_shared<const OccupancyGrid>(std::move(grid));
  FreeNavigationAction action;
  action.goal = Pose2(19.0, 8.0, 0.0);
  action.speed_mps = 0.4;
  const Pose2 start(4.0, 8.0, 0.0);
  {
    FreeNavigationController blocked(action, MecanumPlatformModel(), map, FreeNavigationParams{});
    const ControlOutput out = blocked.Step(OdometryInput(start, kDt));
    EXPECT_THAT(std::string(out.failure.message()), HasSubstr("cannot be reached"));
  }
  const LoadOutline lifted{Pose2(12.0, 8.0, 0.0), Eigen::Vector2d(1.0, 0.7)};
  FreeNavigationController controller(action, MecanumPlatformModel(), map, FreeNavigationParams{},
                                      false, MovedLoads{{lifted}, {}});
  KinematicOmni robot(start);
  bool done = false;
  for (int step = 0; step < 30000 && !done; ++step) {
    const ControlOutput out = controller.Step(OdometryInput(robot.pose(), kDt));
    ASSERT_TRUE(out.failure.ok()) << out.failure;
    done = out.done;
    robot.Step(out.command, kDt);
  }
  EXPECT_TRUE(done);
  EXPECT_TRUE(robot.pose().IsNear(action.goal, 0.05, 0.05)) << robot.pose().DebugString();
}

// A trolley the platform set down in the door (the map does not show it there) closes the
// door for the plan; planning from under it (right after the undock) it is left off, or the
// start would be in collision.
TEST(FreeNavigationControllerTest, ATrolleySetDownIsAnObstacleUnlessTheRobotIsUnderIt) {
  const std::shared_ptr<const OccupancyGrid> map = DoorMap();
  FreeNavigationAction action;
  action.goal = Pose2(19.0, 8.0, 0.0);
  action.speed_mps = 0.4;
  // A wide trolley across the whole 4 m door.
  const LoadOutline in_door{Pose2(12.0, 8.0, (kPi / 2)), Eigen::Vector2d(4.4, 1.0)};
  FreeNavigationController blocked(action, MecanumPlatformModel(), map, FreeNavigationParams{},
                                   false, MovedLoads{{}, {in_door}});
  const ControlOutput refused = blocked.Step(OdometryInput(Pose2(4.0, 8.0, 0.0), kDt));
  EXPECT_THAT(std::string(refused.failure.message()), HasSubstr("cannot be reached"));

  FreeNavigationController from_under(action, MecanumPlatformModel(), map, FreeNavigationParams{},
                                      false, MovedLoads{{}, {in_door}});
  const ControlOutput planned = from_under.Step(OdometryInput(Pose2(12.0, 8.0, 0.0), kDt));
  EXPECT_TRUE(planned.failure.ok()) << planned.failure;
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

/// An axis-aligned box that is in the world but not on the map.
struct UnmappedBox {
  double x0, y0, x1, y1;
};

/// The car's 180° laser (181 beams, 30 m) against unmapped boxes only (the map's walls are far
/// from where these tests drive): the slab test per beam.
LaserScanSample ScanOf(const std::vector<UnmappedBox>& boxes, const Pose2& laser_in_world) {
  LaserScanSample scan;
  scan.name = "laser";
  scan.angle_min_rad = -kPi / 2.0;
  scan.angle_increment_rad = kPi / 180.0;
  scan.range_max_m = 30.0;
  for (int i = 0; i <= 180; ++i) {
    const double a = laser_in_world.yaw_rad() + scan.angle_min_rad + i * scan.angle_increment_rad;
    const double dx = std::cos(a);
    const double dy = std::sin(a);
    double best = std::numeric_limits<double>::infinity();
    for (const UnmappedBox& b : boxes) {
      double t_in = -1e9;
      double t_out = 1e9;
      for (const auto& [o, d, lo, hi] : {std::tuple{laser_in_world.x_m(), dx, b.x0, b.x1},
                                         std::tuple{laser_in_world.y_m(), dy, b.y0, b.y1}}) {
        if (std::abs(d) < 1e-12) {
          if (o < lo || o > hi) t_in = 1e9;
          continue;
        }
        const double t0 = (lo - o) / d;
        const double t1 = (hi - o) / d;
        t_in = std::max(t_in, std::min(t0, t1));
        t_out = std::min(t_out, std::max(t0, t1));
      }
      if (t_in <= t_out && t_in > 0.0) best = std::min(best, t_in);
    }
    scan.ranges_m.push_back(best <= scan.range_max_m ? static_cast<float>(best)
                                                     : std::numeric_limits<float>::infinity());
  }
  return scan;
}

/// The footprint overlaps the box.
bool Touches(const RobotModel& model, const Pose2& pose, const UnmappedBox& b) {
  // Sample the footprint's outline and interior on a 2 cm grid.
  for (double x = -0.15; x <= 0.75; x += 0.02) {
    for (double y = -0.30; y <= 0.30; y += 0.02) {
      const Eigen::Vector2d p = pose.TransformPoint(Eigen::Vector2d(x, y));
      if (p.x() >= b.x0 && p.x() <= b.x1 && p.y() >= b.y0 && p.y() <= b.y1) return true;
    }
  }
  (void)model;
  return false;
}

struct CarRun {
  bool done = false;
  bool touched = false;
  absl::Status failure;
  Pose2 end;
  double end_speed_mps = 1.0;
};

/// The Ackermann robot along the corridor's middle (y = 12 m) towards (9.5, 12) with the boxes
/// seen by its laser (10 Hz) but not on the map.
CarRun DriveAmongUnmappedBoxes(const std::vector<UnmappedBox>& boxes, bool avoid,
                               double boxes_appear_at_x_m = -1e9) {
  const RobotModel car = AckermannDeliveryModel();
  FreeNavigationAction action;
  action.goal = Pose2(9.5, 12.0, 0.0);
  action.speed_mps = 0.5;
  FreeNavigationParams params;
  params.ackermann.avoid_obstacles = avoid;
  FreeNavigationController controller(action, car, DoorMap(), params);
  KinematicCar robot(Pose2(2.0, 12.0, 0.0), car);
  const Pose2 laser_in_base(0.70, 0.0, 0.0);
  CarRun run;
  bool appeared = false;
  for (int step = 0; step < 6000; ++step) {
    ControlInput input = OdometryInput(robot.pose(), kDt);
    appeared = appeared || robot.pose().x_m() >= boxes_appear_at_x_m;
    if (step % 5 == 0) {
      input.perception.laser =
          ScanOf(appeared ? boxes : std::vector<UnmappedBox>{}, robot.pose() * laser_in_base);
      input.perception.laser_in_base = laser_in_base;
    }
    const ControlOutput out = controller.Step(input);
    run.end_speed_mps = std::abs(out.command.vx_mps);
    if (!out.failure.ok()) {
      run.failure = out.failure;
      break;
    }
    if (out.done) {
      run.done = true;
      break;
    }
    robot.Step(out.command, kDt);
    for (const UnmappedBox& b : boxes) run.touched = run.touched || Touches(car, robot.pose(), b);
  }
  run.end = robot.pose();
  return run;
}

// VFH+ in Ackermann free navigation: a box that is not on the map stands on the planned
// straight line; the car steers round it and still reaches the goal; followed blind (the
// baseline) it drives into it.
TEST(FreeNavigationControllerTest, AnAckermannRobotSteersRoundABoxThatIsNotOnTheMap) {
  const std::vector<UnmappedBox> box = {{5.2, 11.8, 5.8, 12.4}};
  const CarRun avoided = DriveAmongUnmappedBoxes(box, /*avoid=*/true);
  ASSERT_TRUE(avoided.failure.ok()) << avoided.failure;
  EXPECT_TRUE(avoided.done) << avoided.end.DebugString();
  EXPECT_FALSE(avoided.touched);
  EXPECT_TRUE(avoided.end.IsNear(Pose2(9.5, 12.0, 0.0), 0.15, DegToRad(8)))
      << avoided.end.DebugString();

  const CarRun blind = DriveAmongUnmappedBoxes(box, /*avoid=*/false);
  EXPECT_TRUE(blind.touched);
}

// Unmapped obstacles in the way: a wall right across the corridor, seen from the start or
// stepping out 0.35 m before the car's nose. The replan round what the laser has seen finds no
// way, and the action fails with the reason; the car never touches the wall, hangs or drives
// on.
TEST(FreeNavigationControllerTest, AnAckermannRobotBlockedByUnmappedObstaclesStopsAndFails) {
  const std::vector<UnmappedBox> wall = {{5.0, 0.0, 5.4, 16.0}};
  for (const double appear_at_x_m : {-1e9, 3.9}) {
    SCOPED_TRACE(appear_at_x_m);
    const CarRun run = DriveAmongUnmappedBoxes(wall, /*avoid=*/true, appear_at_x_m);
    EXPECT_FALSE(run.done);
    EXPECT_FALSE(run.touched) << run.end.DebugString();
    EXPECT_EQ(run.failure.code(), absl::StatusCode::kNotFound) << run.failure;
    EXPECT_THAT(run.failure.message(), HasSubstr("round the obstacles the laser has seen"));
    EXPECT_EQ(run.end_speed_mps, 0.0);
  }
}

}  // namespace
}  // namespace fleetnav::agent
