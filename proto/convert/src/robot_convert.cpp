#include "fleetnav/proto/robot_convert.hpp"

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/geometry_convert.hpp"

namespace fleetnav {
namespace {

v1::Kinematics ToProto(Kinematics kinematics) {
  switch (kinematics) {
    case Kinematics::kDifferential:
      return v1::KINEMATICS_DIFFERENTIAL;
    case Kinematics::kOmnidirectional:
      return v1::KINEMATICS_OMNIDIRECTIONAL;
    case Kinematics::kAckermann:
      return v1::KINEMATICS_ACKERMANN;
  }
  return v1::KINEMATICS_UNSPECIFIED;
}

absl::StatusOr<Kinematics> KinematicsFromProto(int value) {
  switch (value) {
    case v1::KINEMATICS_DIFFERENTIAL:
      return Kinematics::kDifferential;
    case v1::KINEMATICS_OMNIDIRECTIONAL:
      return Kinematics::kOmnidirectional;
    case v1::KINEMATICS_ACKERMANN:
      return Kinematics::kAckermann;
    default:
      return absl::InvalidArgumentError(
          absl::StrCat("model.kinematics: unspecified or unknown value ", value));
  }
}

// SensorType values line up one to one after the UNSPECIFIED slot.
v1::SensorType ToProto(SensorType type) {
  return static_cast<v1::SensorType>(static_cast<int>(type) + 1);
}

absl::StatusOr<SensorType> SensorTypeFromProto(int value, int index) {
  if (value <= v1::SENSOR_TYPE_UNSPECIFIED || value > v1::SENSOR_TYPE_GPS) {
    return absl::InvalidArgumentError(
        absl::StrCat("model.sensors[", index, "].type: unspecified or unknown value ", value));
  }
  return static_cast<SensorType>(value - 1);
}

v1::MotionLimits ToProto(const MotionLimits& limits) {
  v1::MotionLimits out;
  out.set_max_speed_mps(limits.max_speed_mps);
  out.set_max_reverse_speed_mps(limits.max_reverse_speed_mps);
  out.set_max_yaw_rate_radps(limits.max_yaw_rate_radps);
  out.set_max_accel_mps2(limits.max_accel_mps2);
  out.set_max_yaw_accel_radps2(limits.max_yaw_accel_radps2);
  out.set_max_lateral_speed_mps(limits.max_lateral_speed_mps);
  out.set_max_steering_rad(limits.max_steering_rad);
  out.set_max_steering_rate_radps(limits.max_steering_rate_radps);
  return out;
}

MotionLimits FromProto(const v1::MotionLimits& limits) {
  MotionLimits out;
  out.max_speed_mps = limits.max_speed_mps();
  out.max_reverse_speed_mps = limits.max_reverse_speed_mps();
  out.max_yaw_rate_radps = limits.max_yaw_rate_radps();
  out.max_accel_mps2 = limits.max_accel_mps2();
  out.max_yaw_accel_radps2 = limits.max_yaw_accel_radps2();
  out.max_lateral_speed_mps = limits.max_lateral_speed_mps();
  out.max_steering_rad = limits.max_steering_rad();
  out.max_steering_rate_radps = limits.max_steering_rate_radps();
  return out;
}

}  // namespace

v1::RobotModel ToProto(const RobotModel& model) {
  v1::RobotModel out;
  out.set_kind_name(model.kind_name);
  out.set_kinematics(ToProto(model.kinematics));
  for (const Eigen::Vector2d& corner : model.footprint_m) *out.add_footprint() = ToProto(corner);
  out.set_wheel_radius_m(model.wheel_radius_m);
  out.set_track_m(model.track_m);
  out.set_wheelbase_m(model.wheelbase_m);
  out.set_encoder_ticks_per_rev(model.encoder_ticks_per_rev);
  out.set_mass_kg(model.mass_kg);
  out.set_height_m(model.height_m);
  out.set_has_lift(model.has_lift);
  *out.mutable_limits() = ToProto(model.limits);
  for (const SensorMount& sensor : model.sensors) {
    v1::SensorMount* wire = out.add_sensors();
    wire->set_name(sensor.name);
    wire->set_type(ToProto(sensor.type));
    *wire->mutable_pose_in_base() = ToProto(sensor.pose_in_base);
    wire->set_z_m(sensor.z_m);
  }
  return out;
}

absl::StatusOr<RobotModel> FromProto(const v1::RobotModel& model) {
  RobotModel out;
  out.kind_name = model.kind_name();
  ASSIGN_OR_RETURN(out.kinematics, KinematicsFromProto(model.kinematics()));
  for (int i = 0; i < model.footprint_size(); ++i) {
    ASSIGN_OR_RETURN(Eigen::Vector2d corner,
                     FromProto(model.footprint(i), absl::StrCat("model.footprint[", i, "]")));
    out.footprint_m.push_back(corner);
  }
  out.wheel_radius_m = model.wheel_radius_m();
  out.track_m = model.track_m();
  out.wheelbase_m = model.wheelbase_m();
  out.encoder_ticks_per_rev = model.encoder_ticks_per_rev();
  out.mass_kg = model.mass_kg();
  out.height_m = model.height_m();
  out.has_lift = model.has_lift();
  out.limits = FromProto(model.limits());
  for (int i = 0; i < model.sensors_size(); ++i) {
    const v1::SensorMount& wire = model.sensors(i);
    SensorMount sensor;
    sensor.name = wire.name();
    ASSIGN_OR_RETURN(sensor.type, SensorTypeFromProto(wire.type(), i));
    ASSIGN_OR_RETURN(sensor.pose_in_base,
                     FromProto(wire.pose_in_base(), absl::StrCat("model.sensors[", i, "].pose")));
    sensor.z_m = wire.z_m();
    out.sensors.push_back(sensor);
  }
  RETURN_IF_ERROR(out.Validate());
  return out;
}

}  // namespace fleetnav
