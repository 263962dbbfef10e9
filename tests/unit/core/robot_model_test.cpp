#include "fleetnav/core/robot_model.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "fleetnav/core/angles.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

void ExpectInvalid(const absl::Status& status, const std::string& needle) {
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << status;
  EXPECT_THAT(std::string(status.message()), HasSubstr(needle));
}

struct Extent {
  double min_x, max_x, min_y, max_y;
};

Extent FootprintExtent(const RobotModel& model) {
  Extent e{1e9, -1e9, 1e9, -1e9};
  for (const Eigen::Vector2d& p : model.footprint_m) {
    e.min_x = std::min(e.min_x, p.x());
    e.max_x = std::max(e.max_x, p.x());
    e.min_y = std::min(e.min_y, p.y());
    e.max_y = std::max(e.max_y, p.y());
  }
  return e;
}

void ExpectMount(const RobotModel& model, const std::string& name, SensorType type, double x_m,
                 double y_m, double yaw_rad) {
  const SensorMount* sensor = model.FindSensor(name);
  ASSERT_NE(sensor, nullptr) << name;
  EXPECT_EQ(sensor->type, type) << name;
  EXPECT_TRUE(sensor->pose_in_base.IsNear(Pose2(x_m, y_m, yaw_rad), 1e-9, 1e-9))
      << name << ": " << sensor->pose_in_base.DebugString();
}

TEST(RobotModelTest, PresetsAreValid) {
  for (const RobotModel& model :
       {LelyVectorModel(), MecanumPlatformModel(), AckermannDeliveryModel()}) {
    EXPECT_TRUE(model.Validate().ok()) << model.kind_name << ": " << model.Validate();
  }
}

TEST(RobotModelTest, LelyVectorMatchesTheThesis) {
  const RobotModel lely = LelyVectorModel();
  EXPECT_EQ(lely.kind_name, "lely-vector");
  EXPECT_EQ(lely.kinematics, Kinematics::kDifferential);
  EXPECT_DOUBLE_EQ(lely.wheel_radius_m, 0.15);
  EXPECT_DOUBLE_EQ(lely.track_m, 0.92);
  EXPECT_NEAR(lely.wheelbase_m, 0.71, 1e-12);  // axle to swivel caster
  EXPECT_DOUBLE_EQ(lely.mass_kg, 1485.0);
  EXPECT_DOUBLE_EQ(lely.height_m, 1.90);
  EXPECT_EQ(lely.encoder_ticks_per_rev, 4096);
  EXPECT_DOUBLE_EQ(lely.limits.max_speed_mps, 0.5);
  EXPECT_DOUBLE_EQ(lely.limits.max_reverse_speed_mps, 0.0);
  EXPECT_DOUBLE_EQ(lely.limits.max_lateral_speed_mps, 0.0);

  // 2.27 x 1.60 m body centred on the thesis's point C, 0.26 m ahead of the axle.
  const Extent e = FootprintExtent(lely);
  EXPECT_NEAR(e.max_x - e.min_x, 2.27, 1e-12);
  EXPECT_NEAR(e.max_y - e.min_y, 1.60, 1e-12);
  EXPECT_NEAR((e.max_x + e.min_x) / 2.0, 0.26, 1e-12);
  EXPECT_NEAR(e.max_y + e.min_y, 0.0, 1e-12);

  ExpectMount(lely, "ultrasonic_left", SensorType::kUltrasonic, 1.57, 0.25, kPi / 2.0);
  ExpectMount(lely, "ultrasonic_right", SensorType::kUltrasonic, 1.57, -0.25, -kPi / 2.0);
  ExpectMount(lely, "inductive_left", SensorType::kInductive, 0.485, 0.05, 0.0);
  ExpectMount(lely, "inductive_right", SensorType::kInductive, 0.485, -0.05, 0.0);
  ExpectMount(lely, "wheel_encoder_left", SensorType::kWheelEncoder, 0.0, 0.46, 0.0);
  ExpectMount(lely, "wheel_encoder_right", SensorType::kWheelEncoder, 0.0, -0.46, 0.0);
  EXPECT_DOUBLE_EQ(lely.FindSensor("inductive_left")->z_m, 0.04);
  ASSERT_NE(lely.FindSensor("imu"), nullptr);
  ASSERT_NE(lely.FindSensor("charger_contact"), nullptr);
  ASSERT_NE(lely.FindSensor("bumper"), nullptr);
  EXPECT_EQ(lely.FindSensor("laser"), nullptr);
}

TEST(RobotModelTest, MecanumPlatformMatchesTheKukaThesis) {
  const RobotModel mecanum = MecanumPlatformModel();
  EXPECT_EQ(mecanum.kinematics, Kinematics::kOmnidirectional);
  const Extent e = FootprintExtent(mecanum);
  EXPECT_NEAR(e.max_x - e.min_x, 0.788, 1e-12);
  EXPECT_NEAR(e.max_y - e.min_y, 0.480, 1e-12);
  EXPECT_NEAR(e.max_x + e.min_x, 0.0, 1e-12);  // base_link at the platform centre
  EXPECT_GT(mecanum.limits.max_lateral_speed_mps, 0.0);
  EXPECT_GT(mecanum.wheelbase_m, 0.0);
  const SensorMount* laser = mecanum.FindSensor("laser");
  ASSERT_NE(laser, nullptr);
  EXPECT_EQ(laser->type, SensorType::kLaser);
  EXPECT_GT(laser->pose_in_base.x_m(), 0.0);  // at the front
  EXPECT_LE(laser->pose_in_base.x_m(), e.max_x);
}

TEST(RobotModelTest, AckermannDeliveryHasBicycleGeometryAndSensors) {
  const RobotModel car = AckermannDeliveryModel();
  EXPECT_EQ(car.kinematics, Kinematics::kAckermann);
  EXPECT_DOUBLE_EQ(car.wheelbase_m, 0.6);
  EXPECT_DOUBLE_EQ(car.limits.max_steering_rad, 0.5);
  const Extent e = FootprintExtent(car);
  EXPECT_NEAR(e.max_x - e.min_x, 0.9, 1e-12);
  EXPECT_NEAR(e.max_y - e.min_y, 0.6, 1e-12);
  EXPECT_LT(e.min_x, 0.0);  // base_link on the rear axle, inside the body
  EXPECT_GT(e.max_x, car.wheelbase_m);
  for (SensorType type :
       {SensorType::kLaser, SensorType::kGps, SensorType::kImu, SensorType::kWheelEncoder}) {
    EXPECT_TRUE(std::any_of(car.sensors.begin(), car.sensors.end(),
                            [type](const SensorMount& s) { return s.type == type; }));
  }
}

TEST(RobotModelTest, ByKind) {
  for (const char* kind : {"lely-vector", "mecanum-platform", "ackermann-delivery"}) {
    absl::StatusOr<RobotModel> model = RobotModelByKind(kind);
    ASSERT_TRUE(model.ok()) << kind;
    EXPECT_EQ(model->kind_name, kind);
  }
  const absl::Status status = RobotModelByKind("hovercraft").status();
  EXPECT_EQ(status.code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(status.message()), HasSubstr("hovercraft"));
}

TEST(RobotModelTest, CircumscribedRadius) {
  RobotModel model = MecanumPlatformModel();
  EXPECT_NEAR(model.CircumscribedRadius(), std::hypot(0.394, 0.240), 1e-12);
  const Extent e = FootprintExtent(LelyVectorModel());
  EXPECT_NEAR(LelyVectorModel().CircumscribedRadius(), std::hypot(e.max_x, e.max_y), 1e-12);
}

TEST(RobotModelTest, ValidateRejectsBadModels) {
  RobotModel model = LelyVectorModel();
  model.footprint_m.resize(2);
  ExpectInvalid(model.Validate(), "footprint_m must have at least 3 points, got 2");

  model = LelyVectorModel();
  std::reverse(model.footprint_m.begin(), model.footprint_m.end());
  ExpectInvalid(model.Validate(), "counter-clockwise");

  model = LelyVectorModel();
  model.wheel_radius_m = -0.15;
  ExpectInvalid(model.Validate(), "wheel_radius_m must be finite and > 0, got -0.15");

  model = LelyVectorModel();
  model.track_m = 0.0;
  ExpectInvalid(model.Validate(), "track_m");

  model = LelyVectorModel();
  model.limits.max_speed_mps = 0.0;
  ExpectInvalid(model.Validate(), "limits.max_speed_mps must be finite and > 0");

  model = LelyVectorModel();
  model.limits.max_yaw_rate_radps = std::nan("");
  ExpectInvalid(model.Validate(), "limits.max_yaw_rate_radps must be finite and >= 0, got nan");

  model = LelyVectorModel();
  model.limits.max_accel_mps2 = -1.0;
  ExpectInvalid(model.Validate(), "limits.max_accel_mps2");

  model = LelyVectorModel();
  model.limits.max_lateral_speed_mps = 0.2;
  ExpectInvalid(model.Validate(), "max_lateral_speed_mps must be 0");

  model = AckermannDeliveryModel();
  model.limits.max_steering_rad = 0.0;
  ExpectInvalid(model.Validate(), "limits.max_steering_rad");

  model = LelyVectorModel();
  model.sensors.push_back(model.sensors.front());
  ExpectInvalid(model.Validate(), "duplicate sensor name 'wheel_encoder_left'");

  model = LelyVectorModel();
  model.encoder_ticks_per_rev = 0;
  ExpectInvalid(model.Validate(), "encoder_ticks_per_rev must be > 0");
}

TEST(RobotModelTest, KinematicsNames) {
  EXPECT_EQ(KinematicsName(Kinematics::kDifferential), "differential");
  EXPECT_EQ(KinematicsName(Kinematics::kOmnidirectional), "omnidirectional");
  EXPECT_EQ(KinematicsName(Kinematics::kAckermann), "ackermann");
}

// Carrying a trolley, the platform is as large as the two together: the planner and the tracker
// must keep the trolley's legs off the shelves too.
TEST(RobotModelTest, CarryingALoadGrowsTheFootprintToBoth) {
  const RobotModel platform = MecanumPlatformModel();
  EXPECT_TRUE(platform.has_lift);
  EXPECT_FALSE(LelyVectorModel().has_lift);
  const Eigen::AlignedBox2d grown = platform.CarryingLoad({1.0, 0.7}).FootprintBounds();
  EXPECT_NEAR(grown.min().x(), -0.5, 1e-12);
  EXPECT_NEAR(grown.max().x(), 0.5, 1e-12);
  EXPECT_NEAR(grown.min().y(), -0.35, 1e-12);
  EXPECT_NEAR(grown.max().y(), 0.35, 1e-12);
  // A load shorter than the platform leaves the platform's length.
  const Eigen::AlignedBox2d short_load = platform.CarryingLoad({0.5, 0.9}).FootprintBounds();
  EXPECT_NEAR(short_load.max().x(), 0.394, 1e-12);
  EXPECT_NEAR(short_load.max().y(), 0.45, 1e-12);
  EXPECT_TRUE(platform.CarryingLoad({1.0, 0.7}).Validate().ok());
}

}  // namespace
}  // namespace fleetnav
