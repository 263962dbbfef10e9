#include "fleetnav/proto/sensor_convert.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

void ExpectInvalid(const absl::StatusOr<ActuatorCommand>& result, const std::string& field) {
  ASSERT_FALSE(result.ok()) << "expected InvalidArgument naming '" << field << "'";
  EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument) << result.status();
  EXPECT_THAT(std::string(result.status().message()), HasSubstr(field));
}

SensorFrame SampleFrame() {
  SensorFrame frame;
  frame.tick = 9001;
  frame.stamp_ns = 450'050'000'000;
  frame.control_period_s = 0.05;
  frame.encoders = {{"left", 123456}, {"right", -42}};
  frame.imu = {0.12, -0.5, 0.02};
  frame.ultrasonic = {{"ultrasonic_left", 0.48, true}, {"ultrasonic_right", 3.0, false}};
  frame.inductive = {{"inductive_left", true}, {"inductive_right", false}};
  frame.lasers = {{"laser", -1.5, 0.01, 30.0, {1.0f, 2.5f, 29.75f, 30.0f}}};
  frame.charger_contact = true;
  frame.bumper = false;
  frame.gps = GpsFix{12.5, -7.25, 0.8};
  frame.lift_loaded = true;
  frame.steering_angle_rad = -0.3125;
  return frame;
}

TEST(SensorFrameConvertTest, RoundTripsEveryField) {
  const SensorFrame frame = SampleFrame();
  const SensorFrame back = FromProto(ToProto(frame));
  EXPECT_EQ(back.tick, frame.tick);
  EXPECT_EQ(back.stamp_ns, frame.stamp_ns);
  EXPECT_EQ(back.control_period_s, frame.control_period_s);
  ASSERT_EQ(back.encoders.size(), 2u);
  EXPECT_EQ(back.encoders[0].name, "left");
  EXPECT_EQ(back.encoders[0].ticks, 123456);
  EXPECT_EQ(back.encoders[1].name, "right");
  EXPECT_EQ(back.encoders[1].ticks, -42);
  EXPECT_EQ(back.imu.gyro_z_radps, 0.12);
  EXPECT_EQ(back.imu.accel_x_mps2, -0.5);
  EXPECT_EQ(back.imu.accel_y_mps2, 0.02);
  ASSERT_EQ(back.ultrasonic.size(), 2u);
  EXPECT_EQ(back.ultrasonic[0].name, "ultrasonic_left");
  EXPECT_EQ(back.ultrasonic[0].range_m, 0.48);
  EXPECT_TRUE(back.ultrasonic[0].echo);
  EXPECT_FALSE(back.ultrasonic[1].echo);
  ASSERT_EQ(back.inductive.size(), 2u);
  EXPECT_TRUE(back.inductive[0].detected);
  EXPECT_FALSE(back.inductive[1].detected);
  EXPECT_EQ(back.inductive[1].name, "inductive_right");
  ASSERT_EQ(back.lasers.size(), 1u);
  EXPECT_EQ(back.lasers[0].name, "laser");
  EXPECT_EQ(back.lasers[0].angle_min_rad, -1.5);
  EXPECT_EQ(back.lasers[0].angle_increment_rad, 0.01);
  EXPECT_EQ(back.lasers[0].range_max_m, 30.0);
  EXPECT_EQ(back.lasers[0].ranges_m, frame.lasers[0].ranges_m);
  EXPECT_TRUE(back.charger_contact);
  EXPECT_FALSE(back.bumper);
  ASSERT_TRUE(back.gps.has_value());
  EXPECT_EQ(back.gps->x_m, 12.5);
  EXPECT_EQ(back.gps->y_m, -7.25);
  EXPECT_EQ(back.gps->stddev_m, 0.8);
  EXPECT_TRUE(back.lift_loaded);
  ASSERT_TRUE(back.steering_angle_rad.has_value());
  EXPECT_EQ(*back.steering_angle_rad, -0.3125);
}

TEST(SensorFrameConvertTest, NoGpsStaysAbsent) {
  SensorFrame frame = SampleFrame();
  frame.gps.reset();
  const v1::SensorFrame wire = ToProto(frame);
  EXPECT_FALSE(wire.has_gps());
  EXPECT_FALSE(FromProto(wire).gps.has_value());
}

TEST(SensorFrameConvertTest, NoSteeringAngleStaysAbsent) {
  SensorFrame frame = SampleFrame();
  frame.steering_angle_rad.reset();
  const v1::SensorFrame wire = ToProto(frame);
  EXPECT_FALSE(wire.has_steering_angle());
  EXPECT_FALSE(FromProto(wire).steering_angle_rad.has_value());
}

TEST(ActuatorCommandConvertTest, EveryDriveKindRoundTrips) {
  const ActuatorCommand commands[] = {
      {7, Twist2{0.3, -0.1, 0.25}},
      {8, WheelSpeeds{2.0, -1.5}},
      {9, AckermannDrive{0.8, -0.35}},
      {10, Twist2{}, /*lift_raised=*/true},
  };
  for (const ActuatorCommand& command : commands) {
    const v1::ActuatorCommand wire = ToProto(command);
    EXPECT_NE(wire.command_case(), v1::ActuatorCommand::COMMAND_NOT_SET);
    const absl::StatusOr<ActuatorCommand> back = FromProto(wire);
    ASSERT_TRUE(back.ok()) << back.status();
    EXPECT_EQ(back->tick, command.tick);
    EXPECT_EQ(back->lift_raised, command.lift_raised);
    ASSERT_EQ(back->drive.index(), command.drive.index());
    if (const auto* twist = std::get_if<Twist2>(&command.drive)) {
      const auto& got = std::get<Twist2>(back->drive);
      EXPECT_EQ(got.vx_mps, twist->vx_mps);
      EXPECT_EQ(got.vy_mps, twist->vy_mps);
      EXPECT_EQ(got.yaw_rate_radps, twist->yaw_rate_radps);
    } else if (const auto* wheels = std::get_if<WheelSpeeds>(&command.drive)) {
      const auto& got = std::get<WheelSpeeds>(back->drive);
      EXPECT_EQ(got.left_radps, wheels->left_radps);
      EXPECT_EQ(got.right_radps, wheels->right_radps);
    } else {
      const auto& expected = std::get<AckermannDrive>(command.drive);
      const auto& got = std::get<AckermannDrive>(back->drive);
      EXPECT_EQ(got.speed_mps, expected.speed_mps);
      EXPECT_EQ(got.steering_rad, expected.steering_rad);
    }
  }
}

TEST(ActuatorCommandConvertTest, RefusesCommandWithNoDrive) {
  v1::ActuatorCommand wire;
  wire.set_tick(3);
  const absl::StatusOr<ActuatorCommand> result = FromProto(wire);
  ExpectInvalid(result, "command");
  EXPECT_THAT(std::string(result.status().message()), HasSubstr("no drive"));
}

TEST(ActuatorCommandConvertTest, RefusesNanInEveryDriveKind) {
  v1::ActuatorCommand twist = ToProto(ActuatorCommand{1, Twist2{0.1, 0.0, 0.0}});
  twist.mutable_twist()->set_yaw_rate_radps(kNan);
  ExpectInvalid(FromProto(twist), "command");
  EXPECT_THAT(std::string(FromProto(twist).status().message()), HasSubstr("finite"));

  v1::ActuatorCommand wheels = ToProto(ActuatorCommand{1, WheelSpeeds{1.0, 1.0}});
  wheels.mutable_differential()->set_left_wheel_radps(kNan);
  ExpectInvalid(FromProto(wheels), "command");

  v1::ActuatorCommand ackermann = ToProto(ActuatorCommand{1, AckermannDrive{0.5, 0.1}});
  ackermann.mutable_ackermann()->set_steering_rad(std::numeric_limits<double>::infinity());
  ExpectInvalid(FromProto(ackermann), "command");
}

}  // namespace
}  // namespace fleetnav
