// The agent's only wheel odometry: encoders per kinematics fused with the gyro in the EKF.
#include "fleetnav/localization/odometry_front_end.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::localization {
namespace {

using ::testing::HasSubstr;

constexpr double kPeriodS = 0.02;

double MetersPerTick(const RobotModel& model) {
  return 2.0 * kPi * model.wheel_radius_m / model.encoder_ticks_per_rev;
}

SensorFrame DiffFrame(uint64_t tick, int64_t left_ticks, int64_t right_ticks,
                      double gyro_radps = 0.0) {
  SensorFrame frame;
  frame.tick = tick;
  frame.stamp_ns = static_cast<int64_t>(tick) * 20'000'000;
  frame.control_period_s = kPeriodS;
  frame.encoders = {{"left", left_ticks}, {"right", right_ticks}};
  frame.imu.gyro_z_radps = gyro_radps;
  return frame;
}

OdometryFrontEnd Make(const RobotModel& model) {
  absl::StatusOr<OdometryFrontEnd> odometry = OdometryFrontEnd::Create(model, {});
  EXPECT_TRUE(odometry.ok()) << odometry.status();
  return *std::move(odometry);
}

TEST(OdometryFrontEndTest, FirstFrameOnlyLatchesTheEncoders) {
  OdometryFrontEnd odometry = Make(LelyVectorModel());
  ASSERT_TRUE(odometry.Update(DiffFrame(100, 123456, -98765, 0.5)).ok());
  EXPECT_EQ(odometry.pose_in_odom().x_m(), 0.0);
  EXPECT_EQ(odometry.pose_in_odom().yaw_rad(), 0.0);
  EXPECT_EQ(odometry.distance_travelled_m(), 0.0);
}

TEST(OdometryFrontEndTest, StraightTicksGiveTheDistanceDriven) {
  const RobotModel lely = LelyVectorModel();
  OdometryFrontEnd odometry = Make(lely);
  constexpr int kTicksPerFrame = 87;
  constexpr int kFrames = 500;
  for (int i = 0; i <= kFrames; ++i) {
    ASSERT_TRUE(
        odometry.Update(DiffFrame(i, 1000 + i * kTicksPerFrame, -7 + i * kTicksPerFrame)).ok());
  }
  // Then it stands still for a second, so the filtered speed has come to rest.
  for (int i = kFrames + 1; i <= kFrames + 50; ++i) {
    ASSERT_TRUE(
        odometry
            .Update(DiffFrame(i, 1000 + kFrames * kTicksPerFrame, -7 + kFrames * kTicksPerFrame))
            .ok());
  }
  const double expected_m = kFrames * kTicksPerFrame * MetersPerTick(lely);
  EXPECT_NEAR(odometry.distance_travelled_m(), expected_m, 1e-9 * expected_m);
  EXPECT_NEAR(odometry.pose_in_odom().x_m(), expected_m, 0.005 * expected_m);
  EXPECT_NEAR(odometry.pose_in_odom().y_m(), 0.0, 1e-6);
  EXPECT_NEAR(odometry.velocity().vx_mps, 0.0, 0.01);
  EXPECT_TRUE(odometry.standing_still());
}

// The gyro is far better on yaw than the wheels of a heavy robot with a caster: wheels that
// slip into a turn do not turn the estimate.
TEST(OdometryFrontEndTest, YawFollowsTheGyroOverSlippingWheels) {
  OdometryFrontEnd odometry = Make(LelyVectorModel());
  constexpr int kFrames = 250;
  for (int i = 0; i <= kFrames; ++i) {
    ASSERT_TRUE(odometry.Update(DiffFrame(i, 20 * i, 80 * i, /*gyro=*/-0.1)).ok());
  }
  // The wheels alone would say +3.7 rad; the estimate stays within what the EKF's gyro-bias
  // prior (σ = 0.01 rad/s) can absorb of the gyro's -0.5 rad.
  EXPECT_NEAR(odometry.pose_in_odom().yaw_rad(), -0.1 * kFrames * kPeriodS, 0.15);
  EXPECT_LT(odometry.pose_in_odom().y_m(), 0.0);  // bent right, as the gyro says
}

// A parked robot with a biased gyro (0.01 rad/s = 573°/1000 s) keeps its heading: while no
// wheel moves, the gyro is not integrated (zero-velocity update).
TEST(OdometryFrontEndTest, ParkedRobotDoesNotDriftWithGyroBias) {
  OdometryFrontEnd odometry = Make(LelyVectorModel());
  const int frames = static_cast<int>(3200.0 / kPeriodS);
  for (int i = 0; i <= frames; ++i) {
    ASSERT_TRUE(odometry.Update(DiffFrame(i, 500, 500, /*gyro=*/0.01)).ok());
  }
  EXPECT_LT(std::abs(RadToDeg(odometry.pose_in_odom().yaw_rad())), 0.5);
  EXPECT_TRUE(odometry.standing_still());
}

TEST(OdometryFrontEndTest, MecanumWheelsGiveSidewaysMotion) {
  const RobotModel platform = MecanumPlatformModel();
  OdometryFrontEnd odometry = Make(platform);
  // Strafing left: wheels 1 and 4 backwards, 2 and 3 forwards (KUKA thesis eq. 4.15).
  constexpr int kTicks = 40;
  constexpr int kFrames = 200;
  for (int i = 0; i <= kFrames; ++i) {
    SensorFrame frame;
    frame.tick = i;
    frame.stamp_ns = static_cast<int64_t>(i) * 20'000'000;
    frame.encoders = {{"front_left", -kTicks * i},
                      {"front_right", kTicks * i},
                      {"rear_left", kTicks * i},
                      {"rear_right", -kTicks * i}};
    ASSERT_TRUE(odometry.Update(frame).ok());
  }
  const double expected_m = kFrames * kTicks * MetersPerTick(platform);
  EXPECT_NEAR(odometry.pose_in_odom().y_m(), expected_m, 0.02 * expected_m);
  EXPECT_NEAR(odometry.pose_in_odom().x_m(), 0.0, 0.01 * expected_m);
  EXPECT_NEAR(odometry.distance_travelled_m(), expected_m, 1e-6);
}

// The Ackermann robot's odometry, by default (ackermann_yaw_from_steering): the rear encoders
// give the distance, the steering angle the turn (bicycle model); without a steering reading,
// or with the option off, the turn comes from the rear wheels' difference.
TEST(OdometryFrontEndTest, AckermannTurnsByItsSteeringAngle) {
  const RobotModel car = AckermannDeliveryModel();
  OdometryFrontEndParams off;
  off.ackermann_yaw_from_steering = false;
  OdometryFrontEnd steered = Make(car);
  OdometryFrontEnd unsteered = Make(car);
  OdometryFrontEnd by_wheels = *OdometryFrontEnd::Create(car, off);
  constexpr int kTicks = 30;
  constexpr double kSteeringRad = 0.3;
  for (int i = 0; i <= 100; ++i) {
    // Equal rear ticks: the wheels alone would say straight on.
    SensorFrame frame = DiffFrame(i, kTicks * i, kTicks * i);
    ASSERT_TRUE(unsteered.Update(frame).ok());
    frame.steering_angle_rad = kSteeringRad;
    ASSERT_TRUE(steered.Update(frame).ok());
    ASSERT_TRUE(by_wheels.Update(frame).ok());
  }
  const double speed_mps = kTicks * MetersPerTick(car) / kPeriodS;
  EXPECT_NEAR(steered.wheel_velocity().vx_mps, speed_mps, 1e-9);
  EXPECT_NEAR(steered.wheel_velocity().yaw_rate_radps,
              speed_mps * std::tan(kSteeringRad) / car.wheelbase_m, 1e-9);
  EXPECT_NEAR(unsteered.wheel_velocity().yaw_rate_radps, 0.0, 1e-12);
  EXPECT_NEAR(by_wheels.wheel_velocity().yaw_rate_radps, 0.0, 1e-12);
}

TEST(OdometryFrontEndTest, MissingEncoderIsNamed) {
  OdometryFrontEnd lely = Make(LelyVectorModel());
  SensorFrame frame;
  frame.encoders = {{"left", 0}};
  const absl::Status status = lely.Update(frame);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(status.message()), HasSubstr("'right'"));

  OdometryFrontEnd platform = Make(MecanumPlatformModel());
  EXPECT_THAT(std::string(platform.Update(DiffFrame(0, 0, 0)).message()), HasSubstr("front_left"));
}

TEST(OdometryFrontEndTest, BadParamsAreRefused) {
  OdometryFrontEndParams params;
  params.standstill_after_s = -1.0;
  EXPECT_EQ(OdometryFrontEnd::Create(LelyVectorModel(), params).status().code(),
            absl::StatusCode::kInvalidArgument);
  RobotModel broken = LelyVectorModel();
  broken.track_m = 0.0;
  EXPECT_EQ(OdometryFrontEnd::Create(broken, {}).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::localization
