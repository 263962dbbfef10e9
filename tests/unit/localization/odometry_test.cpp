#include "fleetnav/localization/odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace fleetnav::localization {
namespace {

TEST(DiffDriveOdometryTest, StraightAndTurn) {
  DiffDriveOdometry odom(DiffDriveOdometryParams{});
  ASSERT_TRUE(DiffDriveOdometryParams{}.Validate().ok());
  odom.Update(0, 0);
  odom.Update(4096, 4096);  // one revolution each: 2π·0.15 m
  EXPECT_NEAR(odom.pose_in_odom().x_m(), 2.0 * std::numbers::pi * 0.15, 1e-9);
  EXPECT_NEAR(odom.pose_in_odom().yaw_rad(), 0.0, 1e-12);
  const BodyIncrement turn = odom.Update(4096 - 1000, 4096 + 1000);
  EXPECT_NEAR(turn.forward_m, 0.0, 1e-12);
  EXPECT_NEAR(turn.yaw_rad, 2.0 * 2.0 * std::numbers::pi * 0.15 * 1000 / 4096 / 0.92, 1e-9);
}

TEST(DiffDriveOdometryTest, RejectsBadParams) {
  DiffDriveOdometryParams p;
  p.track_m = 0.0;
  EXPECT_EQ(p.Validate().code(), absl::StatusCode::kInvalidArgument);
}

TEST(MecanumOdometryTest, ForwardInverseRoundTrip) {
  MecanumOdometry odom(MecanumOdometryParams{});
  const Eigen::Vector3d twist(0.3, -0.2, 0.4);
  const Eigen::Vector3d back = odom.ForwardKinematics(odom.InverseKinematics(twist));
  EXPECT_TRUE(back.isApprox(twist, 1e-12));
  // Pure strafe: wheels 1 and 4 turn backwards (eq. 4.16).
  const auto wheels = odom.InverseKinematics({0.0, 0.1, 0.0});
  EXPECT_LT(wheels[0], 0.0);
  EXPECT_GT(wheels[1], 0.0);
  EXPECT_GT(wheels[2], 0.0);
  EXPECT_LT(wheels[3], 0.0);
  const BodyIncrement inc = odom.Update(odom.InverseKinematics({0.0, 0.1, 0.0}));
  EXPECT_NEAR(inc.lateral_m, 0.1, 1e-12);
  EXPECT_NEAR(odom.pose_in_odom().y_m(), 0.1, 1e-12);
}

TEST(AckermannOdometryTest, CircleOfKnownRadius) {
  AckermannOdometry odom(AckermannOdometryParams{});
  const double steering = 0.3;
  const double radius = 0.65 / std::tan(steering);
  const int steps = 1000;
  for (int i = 0; i < steps; ++i) odom.Update(2.0 * std::numbers::pi * radius / steps, steering);
  EXPECT_NEAR(odom.pose_in_odom().x_m(), 0.0, 1e-3);
  EXPECT_NEAR(odom.pose_in_odom().y_m(), 0.0, 1e-3);
}

TEST(OdomEkfTest, FusesWheelsAndGyroAndEstimatesBias) {
  OdomEkf ekf(OdomEkfParams{});
  const double bias = 0.02;
  for (int i = 0; i < 2000; ++i) {
    ASSERT_TRUE(ekf.Predict(0.01).ok());
    ekf.FuseWheelTwist({0.5, 0.0, 0.1});
    ekf.FuseGyro(0.1 + bias);
  }
  EXPECT_NEAR(ekf.twist().x(), 0.5, 1e-3);
  EXPECT_NEAR(ekf.twist().z(), 0.1, 5e-3);
  EXPECT_NEAR(ekf.gyro_bias_radps(), bias, 5e-3);
  // 20 s on a circle of radius 5 m: yaw 2 rad.
  EXPECT_NEAR(ekf.pose_in_odom().yaw_rad(), 2.0, 0.05);
  EXPECT_NEAR(ekf.pose_in_odom().x_m(), 5.0 * std::sin(2.0), 0.1);
  const Eigen::Matrix3d cov = ekf.pose_covariance();
  EXPECT_GT(cov(0, 0), 0.0);
  EXPECT_TRUE(cov.isApprox(cov.transpose()));
  EXPECT_EQ(ekf.Predict(-1.0).code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::localization
