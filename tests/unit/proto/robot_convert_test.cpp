#include "fleetnav/proto/robot_convert.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

template <typename T>
void ExpectInvalid(const absl::StatusOr<T>& result, const std::string& field) {
  ASSERT_FALSE(result.ok()) << "expected InvalidArgument naming '" << field << "'";
  EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument) << result.status();
  EXPECT_THAT(std::string(result.status().message()), HasSubstr(field));
}

void ExpectSameModel(const RobotModel& actual, const RobotModel& expected) {
  EXPECT_EQ(actual.kind_name, expected.kind_name);
  EXPECT_EQ(actual.kinematics, expected.kinematics);
  ASSERT_EQ(actual.footprint_m.size(), expected.footprint_m.size());
  for (size_t i = 0; i < expected.footprint_m.size(); ++i) {
    EXPECT_EQ(actual.footprint_m[i], expected.footprint_m[i]) << "footprint_m[" << i << "]";
  }
  EXPECT_EQ(actual.wheel_radius_m, expected.wheel_radius_m);
  EXPECT_EQ(actual.track_m, expected.track_m);
  EXPECT_EQ(actual.wheelbase_m, expected.wheelbase_m);
  EXPECT_EQ(actual.encoder_ticks_per_rev, expected.encoder_ticks_per_rev);
  EXPECT_EQ(actual.mass_kg, expected.mass_kg);
  EXPECT_EQ(actual.height_m, expected.height_m);
  const MotionLimits& a = actual.limits;
  const MotionLimits& e = expected.limits;
  EXPECT_EQ(a.max_speed_mps, e.max_speed_mps);
  EXPECT_EQ(a.max_reverse_speed_mps, e.max_reverse_speed_mps);
  EXPECT_EQ(a.max_yaw_rate_radps, e.max_yaw_rate_radps);
  EXPECT_EQ(a.max_accel_mps2, e.max_accel_mps2);
  EXPECT_EQ(a.max_yaw_accel_radps2, e.max_yaw_accel_radps2);
  EXPECT_EQ(a.max_lateral_speed_mps, e.max_lateral_speed_mps);
  EXPECT_EQ(a.max_steering_rad, e.max_steering_rad);
  EXPECT_EQ(a.max_steering_rate_radps, e.max_steering_rate_radps);
  ASSERT_EQ(actual.sensors.size(), expected.sensors.size());
  for (size_t i = 0; i < expected.sensors.size(); ++i) {
    SCOPED_TRACE(expected.sensors[i].name);
    EXPECT_EQ(actual.sensors[i].name, expected.sensors[i].name);
    EXPECT_EQ(actual.sensors[i].type, expected.sensors[i].type);
    EXPECT_TRUE(actual.sensors[i].pose_in_base.IsNear(expected.sensors[i].pose_in_base, 0.0, 0.0))
        << actual.sensors[i].pose_in_base.DebugString();
    EXPECT_EQ(actual.sensors[i].z_m, expected.sensors[i].z_m);
  }
}

class RobotModelPresetTest : public ::testing::TestWithParam<RobotModel (*)()> {};

TEST_P(RobotModelPresetTest, RoundTripsExactly) {
  const RobotModel model = GetParam()();
  ASSERT_TRUE(model.Validate().ok());
  const v1::RobotModel wire = ToProto(model);
  EXPECT_EQ(wire.kind_name(), model.kind_name);
  EXPECT_NE(wire.kinematics(), v1::KINEMATICS_UNSPECIFIED);
  EXPECT_EQ(wire.sensors_size(), static_cast<int>(model.sensors.size()));
  for (const v1::SensorMount& sensor : wire.sensors()) {
    EXPECT_NE(sensor.type(), v1::SENSOR_TYPE_UNSPECIFIED) << sensor.name();
  }
  const absl::StatusOr<RobotModel> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  ExpectSameModel(*back, model);
}

INSTANTIATE_TEST_SUITE_P(Presets, RobotModelPresetTest,
                         ::testing::Values(&LelyVectorModel, &MecanumPlatformModel,
                                           &AckermannDeliveryModel));

TEST(RobotModelConvertTest, KinematicsMapToTheirWireValues) {
  EXPECT_EQ(ToProto(LelyVectorModel()).kinematics(), v1::KINEMATICS_DIFFERENTIAL);
  EXPECT_EQ(ToProto(MecanumPlatformModel()).kinematics(), v1::KINEMATICS_OMNIDIRECTIONAL);
  EXPECT_EQ(ToProto(AckermannDeliveryModel()).kinematics(), v1::KINEMATICS_ACKERMANN);
}

TEST(RobotModelConvertTest, EverySensorTypeRoundTrips) {
  RobotModel model = AckermannDeliveryModel();
  model.sensors.clear();
  const SensorType all[] = {SensorType::kWheelEncoder, SensorType::kImu,
                            SensorType::kUltrasonic,   SensorType::kInductive,
                            SensorType::kLaser,        SensorType::kChargerContact,
                            SensorType::kBumper,       SensorType::kGps};
  for (SensorType type : all) {
    model.sensors.push_back(
        SensorMount{"s" + std::to_string(static_cast<int>(type)), type, Pose2(0.1, 0.2, 0.3), 0.4});
  }
  const v1::RobotModel wire = ToProto(model);
  EXPECT_EQ(wire.sensors(0).type(), v1::SENSOR_TYPE_WHEEL_ENCODER);
  EXPECT_EQ(wire.sensors(4).type(), v1::SENSOR_TYPE_LASER);
  EXPECT_EQ(wire.sensors(7).type(), v1::SENSOR_TYPE_GPS);
  const absl::StatusOr<RobotModel> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  ExpectSameModel(*back, model);
}

TEST(RobotModelConvertTest, RefusesUnspecifiedOrUnknownKinematics) {
  v1::RobotModel wire = ToProto(LelyVectorModel());
  wire.set_kinematics(v1::KINEMATICS_UNSPECIFIED);
  ExpectInvalid(FromProto(wire), "model.kinematics");
  wire.set_kinematics(static_cast<v1::Kinematics>(99));
  ExpectInvalid(FromProto(wire), "model.kinematics");
}

TEST(RobotModelConvertTest, RefusesUnspecifiedOrUnknownSensorType) {
  v1::RobotModel wire = ToProto(LelyVectorModel());
  wire.mutable_sensors(2)->set_type(v1::SENSOR_TYPE_UNSPECIFIED);
  ExpectInvalid(FromProto(wire), "model.sensors[2].type");
  wire.mutable_sensors(2)->set_type(static_cast<v1::SensorType>(99));
  ExpectInvalid(FromProto(wire), "model.sensors[2].type");
  wire.mutable_sensors(2)->set_type(static_cast<v1::SensorType>(-3));
  ExpectInvalid(FromProto(wire), "model.sensors[2].type");
}

TEST(RobotModelConvertTest, RefusesNonFiniteFootprintAndSensorPose) {
  v1::RobotModel wire = ToProto(MecanumPlatformModel());
  wire.mutable_footprint(1)->set_y_m(std::numeric_limits<double>::quiet_NaN());
  ExpectInvalid(FromProto(wire), "model.footprint[1]");
  wire = ToProto(MecanumPlatformModel());
  wire.mutable_sensors(0)->mutable_pose_in_base()->set_yaw_rad(
      std::numeric_limits<double>::infinity());
  ExpectInvalid(FromProto(wire), "model.sensors[0].pose");
}

TEST(RobotModelConvertTest, RunsModelValidation) {
  v1::RobotModel wire = ToProto(LelyVectorModel());
  wire.set_wheel_radius_m(0.0);
  ExpectInvalid(FromProto(wire), "wheel_radius_m");
  wire = ToProto(LelyVectorModel());
  wire.clear_footprint();
  ExpectInvalid(FromProto(wire), "footprint_m");
  wire = ToProto(LelyVectorModel());
  wire.set_kind_name("");
  ExpectInvalid(FromProto(wire), "kind_name");
}

}  // namespace
}  // namespace fleetnav
