// The reactive controllers closed around a perfect unicycle at the agent's 50 Hz.
#include "fleetnav/robot_agent/control/modes/motion_controllers.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "fleetnav/core/angles.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

using testing::KinematicUnicycle;

constexpr double kDt = 0.02;
constexpr int kMaxSteps = 20000;  // 400 s: far longer than any case here

struct StraightCase {
  double distance_m;
  double speed_mps;
  Pose2 start;
  double yaw_drift_radps;  ///< a disturbance the heading PID must reject (wheel slip, caster)
  double tolerance_m = 0.005;
  double tolerance_deg = 0.3;
};

void PrintTo(const StraightCase& c, std::ostream* os) {
  *os << c.distance_m << " m at " << c.speed_mps << " m/s from " << c.start.DebugString()
      << ", drift " << c.yaw_drift_radps;
}

class StraightControllerTest : public ::testing::TestWithParam<StraightCase> {};

TEST_P(StraightControllerTest, EndsOnTargetWithinLimits) {
  const StraightCase& c = GetParam();
  const MotionProfile profile;
  const MotionLimits limits = LelyVectorModel().limits;
  StraightController controller(c.distance_m, c.speed_mps, profile);
  KinematicUnicycle robot(c.start);
  double last_speed = 0.0;
  int steps = 0;
  bool done = false;
  double last_progress = 0.0;
  for (; steps < kMaxSteps; ++steps) {
    const ControlOutput out = controller.Step(OdometryInput(robot.pose(), kDt));
    ASSERT_GE(out.progress_fraction, last_progress - 1e-12) << "step " << steps;
    last_progress = out.progress_fraction;
    if (out.done) {
      done = true;
      EXPECT_EQ(out.command.vx_mps, 0.0);
      EXPECT_EQ(out.command.yaw_rate_radps, 0.0);
      EXPECT_EQ(out.progress_fraction, 1.0);
      break;
    }
    const Twist2& cmd = out.command;
    ASSERT_GE(cmd.vx_mps, 0.0) << "step " << steps;  // the Lely never reverses
    ASSERT_LE(cmd.vx_mps, c.speed_mps + 1e-12) << "step " << steps;
    ASSERT_LE(cmd.vx_mps, limits.max_speed_mps) << "step " << steps;
    ASSERT_LE(std::abs(cmd.yaw_rate_radps), limits.max_yaw_rate_radps) << "step " << steps;
    EXPECT_EQ(cmd.vy_mps, 0.0);
    // Ramps up no faster than the profile allows (from the creep speed on).
    ASSERT_LE(cmd.vx_mps,
              std::max(last_speed + profile.accel_mps2 * kDt, profile.min_speed_mps) + 1e-12)
        << "step " << steps;
    last_speed = cmd.vx_mps;
    Twist2 applied = cmd;
    applied.yaw_rate_radps += c.yaw_drift_radps;
    robot.Step(applied, kDt);
  }
  ASSERT_TRUE(done) << "not done after " << steps << " steps";
  const Pose2 local = Between(c.start, robot.pose());
  std::printf(
      "[ figures  ] straight %.2f m drift %+.3f: end %+.5f m along, %+.5f m across, "
      "%+.4f deg\n",
      c.distance_m, c.yaw_drift_radps, local.x_m() - c.distance_m, local.y_m(),
      RadToDeg(local.yaw_rad()));
  EXPECT_NEAR(local.x_m(), c.distance_m, 0.005);
  EXPECT_NEAR(local.y_m(), 0.0, c.tolerance_m);
  EXPECT_LT(std::abs(local.yaw_rad()), DegToRad(c.tolerance_deg));
  // It took about as long as the trapezoid says (not a creep all the way).
  const double cruise_s = c.distance_m / c.speed_mps;
  EXPECT_LT(steps * kDt, cruise_s + 2.0 * c.speed_mps / profile.accel_mps2 + 1.0);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, StraightControllerTest,
    ::testing::Values(StraightCase{2.0, 0.25, Pose2(), 0.0},
                      StraightCase{0.5, 0.25, Pose2(1, -2, DegToRad(135)), 0.0},
                      StraightCase{5.0, 0.5, Pose2(-3, 4, DegToRad(-60)), 0.0},
                      StraightCase{0.05, 0.25, Pose2(0, 0, DegToRad(179.9)), 0.0},
                      StraightCase{3.0, 0.3, Pose2(2, 2, DegToRad(20)), 0.005},
                      StraightCase{3.0, 0.3, Pose2(2, 2, DegToRad(20)), -0.005},
                      // A strong steady disturbance (1.1°/s): held within 2 cm of the line.
                      StraightCase{3.0, 0.3, Pose2(2, 2, DegToRad(20)), 0.02, 0.02, 1.0},
                      StraightCase{3.0, 0.3, Pose2(2, 2, DegToRad(20)), -0.02, 0.02, 1.0}));

struct TurnCase {
  double angle_deg;
  double yaw_rate_radps;
  double start_yaw_deg;
};

void PrintTo(const TurnCase& c, std::ostream* os) {
  *os << c.angle_deg << " deg at " << c.yaw_rate_radps << " rad/s from " << c.start_yaw_deg
      << " deg";
}

class TurnControllerTest : public ::testing::TestWithParam<TurnCase> {};

// The unicycle's unwrapped heading shows which way the robot really went: a 270° turn
// accumulates 270° and never takes the 90° short way.
TEST_P(TurnControllerTest, TurnsTheAngleAskedWithinLimits) {
  const TurnCase& c = GetParam();
  const MotionProfile profile;
  const MotionLimits limits = LelyVectorModel().limits;
  const double angle = DegToRad(c.angle_deg);
  TurnController controller(angle, c.yaw_rate_radps, profile);
  KinematicUnicycle robot(Pose2(1.0, 2.0, DegToRad(c.start_yaw_deg)));
  const double start_yaw = robot.unwrapped_yaw_rad();
  double last_rate = 0.0;
  bool done = false;
  int steps = 0;
  for (; steps < kMaxSteps; ++steps) {
    const ControlOutput out = controller.Step(OdometryInput(robot.pose(), kDt));
    if (out.done) {
      done = true;
      EXPECT_EQ(out.command.yaw_rate_radps, 0.0);
      break;
    }
    const Twist2& cmd = out.command;
    ASSERT_EQ(cmd.vx_mps, 0.0) << "step " << steps;  // in place
    ASSERT_LE(std::abs(cmd.yaw_rate_radps), std::abs(c.yaw_rate_radps) + 1e-12) << steps;
    ASSERT_LE(std::abs(cmd.yaw_rate_radps), limits.max_yaw_rate_radps) << steps;
    // Always toward the target, never the other way round.
    ASSERT_GT(cmd.yaw_rate_radps * angle, 0.0) << "step " << steps;
    ASSERT_LE(
        std::abs(cmd.yaw_rate_radps),
        std::max(std::abs(last_rate) + profile.yaw_accel_radps2 * kDt, profile.min_yaw_rate_radps) +
            1e-12)
        << "step " << steps;
    last_rate = cmd.yaw_rate_radps;
    robot.Step(cmd, kDt);
  }
  ASSERT_TRUE(done) << "not done after " << steps << " steps";
  const double turned = robot.unwrapped_yaw_rad() - start_yaw;
  EXPECT_NEAR(RadToDeg(turned), c.angle_deg, 0.3);
  EXPECT_NEAR(robot.pose().x_m(), 1.0, 1e-12);
  EXPECT_NEAR(robot.pose().y_m(), 2.0, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Cases, TurnControllerTest,
                         ::testing::Values(TurnCase{90, 0.3, 0}, TurnCase{-90, 0.3, 45},
                                           TurnCase{270, 0.3, 0}, TurnCase{-270, 0.5, 170},
                                           TurnCase{180, 0.3, -179}, TurnCase{360, 0.4, 10},
                                           TurnCase{5, 0.3, 0}, TurnCase{-1, 0.3, 90}));

TEST(TurnControllerProgressTest, ProgressRisesToOne) {
  TurnController controller(DegToRad(270), 0.3, MotionProfile{});
  KinematicUnicycle robot;
  double last = 0.0;
  for (int i = 0; i < kMaxSteps; ++i) {
    const ControlOutput out = controller.Step(OdometryInput(robot.pose(), kDt));
    ASSERT_GE(out.progress_fraction, last - 1e-12);
    last = out.progress_fraction;
    if (out.done) break;
    robot.Step(out.command, kDt);
  }
  EXPECT_EQ(last, 1.0);
}

}  // namespace
}  // namespace fleetnav::agent
