// The polar move-to-pose law driving a perfect unicycle: it converges on the goal pose from
// ahead and aside, backs onto it with reverse, and its gains are checked.
#include "fleetnav/robot_agent/control/common/polar_pose_control.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "fleetnav/core/angles.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

using testing::KinematicUnicycle;

/// Drives with the law (speed capped, curvature free) until within 2 mm; the heading, which
/// converges more slowly than the distance (the slow eigenvalue of the linearised law is below
/// k_rho), is then within a few hundredths of a radian. Returns the end.
Pose2 DriveToPose(const Pose2& start, const Pose2& goal, bool reverse, bool* went_backwards) {
  KinematicUnicycle robot(start);
  const PolarPoseGains gains;
  *went_backwards = false;
  for (int i = 0; i < 20000; ++i) {
    const PolarPoseCommand c = PolarMoveToPose(robot.pose(), goal, gains, reverse);
    if (c.distance_m < 0.002) break;
    const double v = std::clamp(c.speed_mps, -0.5, 0.5);
    *went_backwards = *went_backwards || v < 0.0;
    robot.Step(Twist2{v, 0.0, v * c.curvature_per_m}, 0.005);
  }
  return robot.pose();
}

TEST(PolarPoseControlTest, ConvergesOnTheGoalPoseFromAheadAndAside) {
  const Pose2 goal(3.0, 1.0, DegToRad(30));
  for (const Pose2& start :
       {Pose2(0.0, 0.0, 0.0), Pose2(0.0, 2.0, DegToRad(-20)), Pose2(1.0, -1.5, DegToRad(60))}) {
    bool backwards = false;
    const Pose2 end = DriveToPose(start, goal, false, &backwards);
    EXPECT_TRUE(end.IsNear(goal, 0.015, 0.05))
        << start.DebugString() << " -> " << end.DebugString();
    EXPECT_FALSE(backwards);
  }
}

TEST(PolarPoseControlTest, ReverseBacksOntoTheGoal) {
  // A parking move: the goal lies behind the robot, facing the same way.
  const Pose2 goal(-2.0, -0.8, 0.0);
  bool backwards = false;
  const Pose2 end = DriveToPose(Pose2(0.0, 0.0, 0.0), goal, true, &backwards);
  EXPECT_TRUE(end.IsNear(goal, 0.015, 0.05)) << end.DebugString();
  EXPECT_TRUE(backwards);
  const PolarPoseCommand c = PolarMoveToPose(Pose2(), goal, PolarPoseGains{}, true);
  EXPECT_LT(c.speed_mps, 0.0);
  EXPECT_LT(std::abs(c.alpha_rad), kPi / 2.0) << "the goal is ahead of the turned-round robot";
}

TEST(PolarPoseControlTest, GainsOutsideTheStableRegionAreRefused) {
  EXPECT_TRUE(PolarPoseGains{}.Validate().ok());
  PolarPoseGains g;
  g.k_beta_per_s = 0.5;
  EXPECT_EQ(g.Validate().code(), absl::StatusCode::kInvalidArgument);
  g = PolarPoseGains{};
  g.k_alpha_per_s = 0.5;  // not > k_rho
  EXPECT_EQ(g.Validate().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::agent
