// What every MotionController that drives on odometry promises: closed around an ideal body of
// its kind, it reports done at the end of its action and then commands standstill, never
// commands beyond the speed its action allows, never NaN, and reports progress that only grows
// from 0 to 1. (Modes that need the map or the laser have their own tests.)
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/robot_agent/control/modes/motion_controllers.hpp"
#include "fleetnav/robot_agent/control/modes/move_controller.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

constexpr double kDt = 0.02;
constexpr int kMaxSteps = 20000;  // 400 s

struct Straight {
  static constexpr double kSpeedMps = 0.3;
  static constexpr double kYawRateRadps = 0.0;
  static std::unique_ptr<MotionController> Make() {
    return std::make_unique<StraightController>(2.5, kSpeedMps, MotionProfile{});
  }
  static Pose2 Goal(const Pose2& start) { return start * Pose2(2.5, 0.0, 0.0); }
  static Pose2 Move(const Pose2& pose, const Twist2& twist) {
    testing::KinematicUnicycle body(pose);
    body.Step(twist, kDt);
    return body.pose();
  }
};

struct Turn {
  static constexpr double kSpeedMps = 0.0;
  static constexpr double kYawRateRadps = 0.4;
  static std::unique_ptr<MotionController> Make() {
    return std::make_unique<TurnController>(-2.0, kYawRateRadps, MotionProfile{});
  }
  static Pose2 Goal(const Pose2& start) { return start * Pose2(0.0, 0.0, -2.0); }
  static Pose2 Move(const Pose2& pose, const Twist2& twist) { return Straight::Move(pose, twist); }
};

struct OmniMove {
  static constexpr double kSpeedMps = 0.25;
  static constexpr double kYawRateRadps = 1e9;  // holds its heading; any correction is fine
  static std::unique_ptr<MotionController> Make() {
    return std::make_unique<MoveController>(MoveAction{0.8, -0.6, kSpeedMps}, std::nullopt,
                                            MecanumPlatformModel(), MoveParams{});
  }
  static Pose2 Goal(const Pose2& start) { return start * Pose2(0.8, -0.6, 0.0); }
  static Pose2 Move(const Pose2& pose, const Twist2& twist) {
    return testing::MovedOmni(pose, twist, kDt);
  }
};

template <typename Mode>
class MotionControllerConformanceTest : public ::testing::Test {};

using Modes = ::testing::Types<Straight, Turn, OmniMove>;
TYPED_TEST_SUITE(MotionControllerConformanceTest, Modes);

TYPED_TEST(MotionControllerConformanceTest, EndsItsActionWithinItsLimitsAndThenStands) {
  const Pose2 start(1.0, -2.0, 0.7);
  std::unique_ptr<MotionController> controller = TypeParam::Make();
  Pose2 pose = start;
  double last_progress = 0.0;
  bool done = false;
  int step = 0;
  for (; step < kMaxSteps && !done; ++step) {
    const ControlOutput out = controller->Step(OdometryInput(pose, kDt));
    ASSERT_TRUE(out.failure.ok()) << out.failure;
    ASSERT_TRUE(std::isfinite(out.command.vx_mps) && std::isfinite(out.command.vy_mps) &&
                std::isfinite(out.command.yaw_rate_radps) && std::isfinite(out.progress_fraction))
        << "step " << step;
    EXPECT_LE(std::hypot(out.command.vx_mps, out.command.vy_mps), TypeParam::kSpeedMps + 1e-6);
    EXPECT_LE(std::abs(out.command.yaw_rate_radps), TypeParam::kYawRateRadps + 1e-6);
    EXPECT_GE(out.progress_fraction, last_progress - 1e-9);
    EXPECT_LE(out.progress_fraction, 1.0 + 1e-9);
    last_progress = out.progress_fraction;
    done = out.done;
    if (!done) pose = TypeParam::Move(pose, out.command);
  }
  ASSERT_TRUE(done) << "not done after " << step << " ticks";
  const Pose2 goal = TypeParam::Goal(start);
  EXPECT_LT((pose.translation() - goal.translation()).norm(), 0.02);
  EXPECT_LT(std::abs(std::remainder(pose.yaw_rad() - goal.yaw_rad(), 2 * kPi)), 0.02);
  EXPECT_NEAR(last_progress, 1.0, 1e-6);
  // Asked again once done, it stands.
  const ControlOutput after = controller->Step(OdometryInput(pose, kDt));
  EXPECT_TRUE(after.done);
  EXPECT_NEAR(std::hypot(after.command.vx_mps, after.command.vy_mps), 0.0, 1e-9);
  EXPECT_NEAR(after.command.yaw_rate_radps, 0.0, 1e-9);
}

}  // namespace
}  // namespace fleetnav::agent
