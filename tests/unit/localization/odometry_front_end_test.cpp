#include "fleetnav/robot_agent/wheel_odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {
namespace {

constexpr double kPeriodS = 0.02;

const RobotModel& Lely() {
  static const RobotModel model = LelyVectorModel();
  return model;
}

double MetersPerTick() { return 2.0 * kPi * Lely().wheel_radius_m / Lely().encoder_ticks_per_rev; }

SensorFrame Frame(uint64_t tick, int64_t left_ticks, int64_t right_ticks, double gyro_radps = 0.0) {
  SensorFrame frame;
  frame.tick = tick;
  frame.stamp_ns = static_cast<int64_t>(tick) * 20'000'000;
  frame.control_period_s = kPeriodS;
  frame.encoders = {{"left", left_ticks}, {"right", right_ticks}};
  frame.imu.gyro_z_radps = gyro_radps;
  return frame;
}

TEST(WheelOdometryTest, FirstFrameOnlySetsTheReference) {
  WheelOdometry odometry(Lely());
  odometry.Update(Frame(100, 123456, -98765, 0.5));
  EXPECT_EQ(odometry.pose_in_odom().x_m(), 0.0);
  EXPECT_EQ(odometry.pose_in_odom().y_m(), 0.0);
  EXPECT_EQ(odometry.pose_in_odom().yaw_rad(), 0.0);
  EXPECT_EQ(odometry.distance_travelled_m(), 0.0);
  // The next frame counts from those ticks, not from zero.
  odometry.Update(Frame(101, 123456 + 40, -98765 + 40, 0.0));
  EXPECT_NEAR(odometry.pose_in_odom().x_m(), 40 * MetersPerTick(), 1e-12);
}

TEST(WheelOdometryTest, StraightTicksGiveExactDistance) {
  WheelOdometry odometry(Lely());
  constexpr int kTicksPerFrame = 87;
  constexpr int kFrames = 500;
  for (int i = 0; i <= kFrames; ++i) {
    odometry.Update(Frame(i, 1000 + i * kTicksPerFrame, -7 + i * kTicksPerFrame));
  }
  const double expected_m = kFrames * kTicksPerFrame * MetersPerTick();
  EXPECT_NEAR(odometry.pose_in_odom().x_m(), expected_m, 1e-9 * expected_m);
  EXPECT_NEAR(odometry.pose_in_odom().y_m(), 0.0, 1e-12);
  EXPECT_NEAR(odometry.pose_in_odom().yaw_rad(), 0.0, 1e-12);
  EXPECT_NEAR(odometry.distance_travelled_m(), expected_m, 1e-9 * expected_m);
  EXPECT_NEAR(odometry.velocity().vx_mps, kTicksPerFrame * MetersPerTick() / kPeriodS, 1e-9);
  EXPECT_NEAR(odometry.velocity().yaw_rate_radps, 0.0, 1e-12);
}

TEST(WheelOdometryTest, BackwardsCountsNegativeXButPositiveDistance) {
  WheelOdometry odometry(Lely());
  for (int i = 0; i <= 100; ++i) odometry.Update(Frame(i, -50 * i, -50 * i));
  const double expected_m = 100 * 50 * MetersPerTick();
  EXPECT_NEAR(odometry.pose_in_odom().x_m(), -expected_m, 1e-9 * expected_m);
  EXPECT_NEAR(odometry.distance_travelled_m(), expected_m, 1e-9 * expected_m);
  EXPECT_LT(odometry.velocity().vx_mps, 0.0);
}

// gyro_weight = 0: the yaw comes from the wheel difference over the track (eq. 3.2), and the
// gyro is ignored even when it reads nonsense.
TEST(WheelOdometryTest, EncoderYawWhenGyroWeightIsZero) {
  WheelOdometry odometry(Lely(), WheelOdometryParams{.gyro_weight = 0.0});
  constexpr int kTicksPerFrame = 30;
  constexpr int kFrames = 200;
  for (int i = 0; i <= kFrames; ++i) {
    odometry.Update(Frame(i, -i * kTicksPerFrame, i * kTicksPerFrame, /*gyro=*/5.0));
  }
  const double expected_yaw = kFrames * 2.0 * kTicksPerFrame * MetersPerTick() / Lely().track_m;
  ASSERT_LT(expected_yaw, kPi);
  EXPECT_NEAR(odometry.pose_in_odom().yaw_rad(), expected_yaw, 1e-9);
  // Turning in place: no translation, no path length.
  EXPECT_NEAR(odometry.pose_in_odom().x_m(), 0.0, 1e-12);
  EXPECT_NEAR(odometry.pose_in_odom().y_m(), 0.0, 1e-12);
  EXPECT_NEAR(odometry.distance_travelled_m(), 0.0, 1e-12);
  EXPECT_NEAR(odometry.velocity().yaw_rate_radps,
              2.0 * kTicksPerFrame * MetersPerTick() / Lely().track_m / kPeriodS, 1e-9);
}

TEST(WheelOdometryTest, EncoderArcMatchesTheClosedForm) {
  WheelOdometry odometry(Lely(), WheelOdometryParams{.gyro_weight = 0.0});
  // Left 40, right 60 ticks per frame: v and ω constant, an arc of radius v/ω.
  constexpr int kFrames = 300;
  for (int i = 0; i <= kFrames; ++i) odometry.Update(Frame(i, 40 * i, 60 * i));
  const double v = 50 * MetersPerTick() / kPeriodS;
  const double w = 20 * MetersPerTick() / Lely().track_m / kPeriodS;
  const double t = kFrames * kPeriodS;
  const double yaw = w * t;
  EXPECT_NEAR(odometry.pose_in_odom().yaw_rad(), yaw, 1e-9);
  // The midpoint rule is exact in heading and second order in position.
  EXPECT_NEAR(odometry.pose_in_odom().x_m(), v / w * std::sin(yaw), 1e-4);
  EXPECT_NEAR(odometry.pose_in_odom().y_m(), v / w * (1.0 - std::cos(yaw)), 1e-4);
}

// gyro_weight = 1 (the default): the yaw follows the gyro whatever the wheels say.
TEST(WheelOdometryTest, GyroYawWhenGyroWeightIsOne) {
  WheelOdometry odometry(Lely());
  constexpr int kFrames = 250;
  for (int i = 0; i <= kFrames; ++i) odometry.Update(Frame(i, 20 * i, 80 * i, /*gyro=*/-0.1));
  EXPECT_NEAR(odometry.pose_in_odom().yaw_rad(), -0.1 * kFrames * kPeriodS, 1e-9);
  EXPECT_NEAR(odometry.velocity().yaw_rate_radps, -0.1, 1e-9);
  // Path length from the mean wheel travel, bent to the right by the gyro.
  const double v = 50 * MetersPerTick() / kPeriodS;
  const double yaw = -0.1 * kFrames * kPeriodS;
  EXPECT_NEAR(odometry.pose_in_odom().x_m(), v / -0.1 * std::sin(yaw), 1e-4);
  EXPECT_LT(odometry.pose_in_odom().y_m(), 0.0);
}

TEST(WheelOdometryTest, BlendedYaw) {
  WheelOdometry odometry(Lely(), WheelOdometryParams{.gyro_weight = 0.25});
  odometry.Update(Frame(0, 0, 0));
  odometry.Update(Frame(1, -100, 100, 0.2));
  const double encoder_dyaw = 200 * MetersPerTick() / Lely().track_m;
  EXPECT_NEAR(odometry.pose_in_odom().yaw_rad(), 0.25 * 0.2 * kPeriodS + 0.75 * encoder_dyaw,
              1e-12);
}

TEST(WheelOdometryTest, FramesWithoutEncodersOrTimeAreIgnored) {
  WheelOdometry odometry(Lely());
  SensorFrame no_encoders;
  no_encoders.stamp_ns = 0;
  odometry.Update(no_encoders);
  odometry.Update(Frame(0, 0, 0));
  odometry.Update(Frame(1, 100, 100));
  const Pose2 before = odometry.pose_in_odom();
  SensorFrame same_time = Frame(1, 200, 200, 1.0);
  odometry.Update(same_time);  // no time passed: nothing integrated
  EXPECT_EQ(odometry.pose_in_odom().x_m(), before.x_m());
  // The reference moved to the latest ticks, so the next frame counts from 200.
  odometry.Update(Frame(2, 300, 300));
  EXPECT_NEAR(odometry.pose_in_odom().x_m(), 200 * MetersPerTick(), 1e-12);
}

}  // namespace
}  // namespace fleetnav::agent
