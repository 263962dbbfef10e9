// Ackermann pure pursuit with what the laser sees: obstacles beside the path leave it alone,
// an obstacle on it engages VFH+ and reports the path obstructed, a wall across it brakes the car
// to a stop and reports blocked; the last metre is driven by the polar move-to-pose law.
#include "fleetnav/robot_agent/control/trackers/ackermann_pure_pursuit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {
namespace {

constexpr double kDt = 0.02;

std::vector<Pose2> StraightPath(double length_m) {
  std::vector<Pose2> path;
  for (double x = 0.0; x <= length_m + 1e-9; x += 0.05) path.emplace_back(x, 0.0, 0.0);
  return path;
}

/// Steps the tracker from the origin, driving straight on, until it is up to speed.
AckermannPurePursuit MovingTracker(const std::vector<Eigen::Vector2d>& obstacles) {
  AckermannPurePursuit tracker(AckermannPurePursuitParams{}, AckermannDeliveryModel());
  tracker.SetPath(StraightPath(8.0));
  tracker.SetObstacles(obstacles);
  return tracker;
}

TEST(AckermannPurePursuitTest, ObstaclesBesideThePathLeaveItAlone) {
  // A corridor 1.2 m wide: 0.3 m to spare each side of the 0.6 m car, more than the margin.
  std::vector<Eigen::Vector2d> walls;
  for (double x = 0.5; x <= 4.0; x += 0.05) {
    walls.emplace_back(x, 0.6);
    walls.emplace_back(x, -0.6);
  }
  AckermannPurePursuit free_tracker = MovingTracker({});
  AckermannPurePursuit walled_tracker = MovingTracker(walls);
  for (int i = 0; i < 50; ++i) {
    const Pose2 pose(0.01 * i, 0.0, 0.0);
    const Twist2 a = free_tracker.Step(pose, kDt);
    const Twist2 b = walled_tracker.Step(pose, kDt);
    ASSERT_DOUBLE_EQ(a.vx_mps, b.vx_mps) << i;
    ASSERT_DOUBLE_EQ(a.yaw_rate_radps, b.yaw_rate_radps) << i;
    ASSERT_FALSE(walled_tracker.path_obstructed());
  }
}

TEST(AckermannPurePursuitTest, AnObstacleOnThePathEngagesVfhPlus) {
  // A 0.6 m box on the line 2.5 m ahead: the car turns away from it before it.
  std::vector<Eigen::Vector2d> box;
  for (double t = 0.0; t <= 0.6; t += 0.02) {
    box.emplace_back(2.5, -0.3 + t);
    box.emplace_back(2.5 + t, -0.3);
    box.emplace_back(2.5 + t, 0.3);
  }
  AckermannPurePursuit tracker = MovingTracker(box);
  Twist2 twist;
  for (int i = 0; i < 10; ++i) twist = tracker.Step(Pose2(), kDt);
  EXPECT_TRUE(tracker.path_obstructed());
  EXPECT_GT(std::abs(twist.yaw_rate_radps), 0.0) << "steers round it";
  EXPECT_FALSE(tracker.blocked());

  AckermannPurePursuitParams blind_params;
  blind_params.avoid_obstacles = false;
  AckermannPurePursuit blind(blind_params, AckermannDeliveryModel());
  blind.SetPath(StraightPath(8.0));
  blind.SetObstacles(box);
  for (int i = 0; i < 10; ++i) twist = blind.Step(Pose2(), kDt);
  EXPECT_FALSE(blind.path_obstructed());
  EXPECT_EQ(twist.yaw_rate_radps, 0.0) << "the baseline drives on at it";
}

TEST(AckermannPurePursuitTest, AWallAcrossThePathBrakesToAStopAndReportsBlocked) {
  AckermannPurePursuit tracker = MovingTracker({});
  Twist2 twist;
  for (int i = 0; i < 100; ++i) twist = tracker.Step(Pose2(), kDt);  // up to speed
  ASSERT_GT(twist.vx_mps, 0.4);
  std::vector<Eigen::Vector2d> wall;
  for (double y = -4.0; y <= 4.0; y += 0.02) wall.emplace_back(1.3, y);
  tracker.SetObstacles(wall);
  double previous = twist.vx_mps;
  for (int i = 0; i < 100; ++i) {
    twist = tracker.Step(Pose2(), kDt);
    ASSERT_TRUE(tracker.blocked()) << i;
    ASSERT_LE(twist.vx_mps, previous + 1e-12) << "only slows down";
    previous = twist.vx_mps;
  }
  EXPECT_EQ(twist.vx_mps, 0.0);
  EXPECT_EQ(twist.yaw_rate_radps, 0.0);
}

TEST(AckermannPurePursuitTest, TheLastMetreFollowsThePolarLaw) {
  // 0.5 m from the goal, 2 cm left of the path's line and parallel to it: the curvature is the
  // polar law's ω / v (−0.56 / m), not pure pursuit's towards its lookahead point (−0.44 / m).
  AckermannPurePursuit tracker(AckermannPurePursuitParams{}, AckermannDeliveryModel());
  tracker.SetPath(StraightPath(3.0));
  const Pose2 pose(2.5, 0.02, 0.0);
  const Twist2 twist = tracker.Step(pose, kDt);
  const PolarPoseCommand polar =
      PolarMoveToPose(pose, Pose2(3.0, 0.0, 0.0), PolarPoseGains{}, /*reverse=*/false);
  ASSERT_GT(twist.vx_mps, 0.0);
  const double max_curvature = std::tan(AckermannDeliveryModel().limits.max_steering_rad) /
                               AckermannDeliveryModel().wheelbase_m;
  ASSERT_LT(std::abs(polar.curvature_per_m), max_curvature);
  EXPECT_NEAR(twist.yaw_rate_radps / twist.vx_mps, polar.curvature_per_m, 1e-9);
  const double lookahead_m = AckermannPurePursuitParams{}.min_lookahead_m;
  const double pure_pursuit = 2.0 * -0.02 / (lookahead_m * lookahead_m + 0.02 * 0.02);
  EXPECT_GT(std::abs(polar.curvature_per_m - pure_pursuit), 0.05);
}

// A car that has passed the end of its path 0.2 m aside (a short manoeuvre it overshot) stops
// there, done, for the goal check to correct; it does not drive on along the end's heading.
// Passed far aside (0.5 m), or passed with most of the path still ahead, it does not count.
TEST(AckermannPurePursuitTest, AnEndPassedALittleAsideIsReached) {
  AckermannPurePursuit tracker(AckermannPurePursuitParams{}, AckermannDeliveryModel());
  tracker.SetPath(StraightPath(1.0));
  tracker.Step(Pose2(0.9, 0.2, 0.0), kDt);
  EXPECT_FALSE(tracker.done());
  tracker.Step(Pose2(1.05, 0.2, 0.0), kDt);
  EXPECT_TRUE(tracker.done());

  AckermannPurePursuit far_aside(AckermannPurePursuitParams{}, AckermannDeliveryModel());
  far_aside.SetPath(StraightPath(1.0));
  far_aside.Step(Pose2(1.05, 0.5, 0.0), kDt);
  EXPECT_FALSE(far_aside.done());

  // A path that loops back: its end lies behind the car at the start, 0.2 m aside.
  std::vector<Pose2> loop;
  for (double a = 0.0; a <= 2 * kPi - 0.1; a += 0.05) {
    loop.emplace_back(1.2 * std::sin(a) + 0.0, 1.2 * (1.0 - std::cos(a)) + 0.0, a);
  }
  loop.emplace_back(-0.1, 0.2, 0.0);
  AckermannPurePursuit looping(AckermannPurePursuitParams{}, AckermannDeliveryModel());
  looping.SetPath(loop);
  looping.Step(Pose2(0.0, 0.0, 0.0), kDt);
  EXPECT_FALSE(looping.done());
}

}  // namespace
}  // namespace fleetnav::agent

namespace fleetnav::agent {
namespace {

/// The speed the tracker settles at driving along the straight path from x = 0 to `until_x`.
double CruiseSpeedWith(const std::vector<double>& clearances_m, double until_x) {
  AckermannPurePursuit tracker(AckermannPurePursuitParams{}, AckermannDeliveryModel());
  tracker.SetPath(StraightPath(12.0));
  tracker.SetClearances(clearances_m);
  double x = 0.0;
  double speed = 0.0;
  while (x < until_x) {
    speed = tracker.Step(Pose2(x, 0.0, 0.0), kDt).vx_mps;
    x += speed * kDt;
  }
  return speed;
}

TEST(AckermannPurePursuitTest, SlowsWhereThePathRunsTightFromBrakingDistanceAhead) {
  const size_t poses = StraightPath(12.0).size();  // every 5 cm
  // A gap with 0.25 m a side from x = 8 m to 9 m; open elsewhere.
  std::vector<double> clearances(poses, 3.0);
  for (size_t i = 160; i <= 180; ++i) clearances[i] = 0.25;
  const AckermannPurePursuitParams params;
  const double open = CruiseSpeedWith({}, 4.0);
  EXPECT_NEAR(open, params.desired_speed_mps, 1e-3);
  // Far from the gap: full speed; within braking distance of it and in it: slowed in proportion.
  EXPECT_NEAR(CruiseSpeedWith(clearances, 4.0), open, 1e-3);
  const double share =
      params.slowest_share + (1.0 - params.slowest_share) * (0.25 - params.tight_clearance_m) /
                                 (params.slow_clearance_m - params.tight_clearance_m);
  EXPECT_NEAR(CruiseSpeedWith(clearances, 8.5), share * params.desired_speed_mps, 0.01);
  // Clearances that do not match the path (another path's) are ignored.
  EXPECT_NEAR(CruiseSpeedWith(std::vector<double>(3, 0.0), 8.5), open, 1e-3);
}

TEST(AckermannPurePursuitTest, SlowingParamsAreChecked) {
  AckermannPurePursuitParams params;
  params.tight_clearance_m = params.slow_clearance_m;
  EXPECT_EQ(params.Validate().code(), absl::StatusCode::kInvalidArgument);
  params = AckermannPurePursuitParams{};
  params.slowest_share = 0.0;
  EXPECT_EQ(params.Validate().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::agent
