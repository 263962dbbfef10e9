#include "fleetnav/proto/sim_convert.hpp"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/robot_convert.hpp"

namespace fleetnav {
namespace {

struct FaultTypePair {
  FaultType type;
  v1::FaultType wire;
};

constexpr FaultTypePair kFaultTypes[] = {
    {FaultType::kHideUltrasonicRegion, v1::FAULT_TYPE_HIDE_ULTRASONIC_REGION},
    {FaultType::kRemoveFenceSegment, v1::FAULT_TYPE_REMOVE_FENCE_SEGMENT},
    {FaultType::kRemoveStripeSegment, v1::FAULT_TYPE_REMOVE_STRIPE_SEGMENT},
    {FaultType::kWheelSlipRegion, v1::FAULT_TYPE_WHEEL_SLIP_REGION},
    {FaultType::kSensorDropout, v1::FAULT_TYPE_SENSOR_DROPOUT},
    {FaultType::kSlowDown, v1::FAULT_TYPE_SLOW_DOWN},
};

}  // namespace

v1::GetWorldResponse ToProto(const SimWorldSummary& world) {
  v1::GetWorldResponse out;
  out.set_world_name(world.world_name);
  out.set_width_m(world.width_m);
  out.set_height_m(world.height_m);
  out.set_control_period_s(world.control_period_s);
  out.set_physics_step_s(world.physics_step_s);
  out.set_sim_time_ns(world.sim_time_ns);
  for (const SimWorldSummary::Robot& robot : world.robots) {
    v1::SimRobotInfo* info = out.add_robots();
    info->set_robot_id(robot.robot_id);
    info->set_attached(robot.attached);
    if (robot.model) *info->mutable_model() = ToProto(*robot.model);
  }
  return out;
}

v1::Twist2 ToProto(const Twist2& twist) {
  v1::Twist2 out;
  out.set_vx_mps(twist.vx_mps);
  out.set_vy_mps(twist.vy_mps);
  out.set_yaw_rate_radps(twist.yaw_rate_radps);
  return out;
}

v1::GroundTruth ToProto(const GroundTruthSnapshot& truth, int64_t start_unix_ms) {
  v1::GroundTruth out;
  out.set_sim_time_ns(truth.sim_time_ns);
  out.set_tick(truth.tick);
  out.set_start_unix_ms(start_unix_ms);
  for (const RobotTruth& robot : truth.robots) {
    v1::RobotGroundTruth* wire = out.add_robots();
    wire->set_robot_id(robot.robot_id);
    *wire->mutable_pose() = ToProto(robot.pose);
    *wire->mutable_velocity() = ToProto(robot.velocity);
    wire->set_up_z(robot.up_z);
    wire->set_collisions(static_cast<uint32_t>(robot.collisions()));
    wire->set_collisions_world(static_cast<uint32_t>(robot.collisions_world));
    wire->set_collisions_robots(static_cast<uint32_t>(robot.collisions_robots));
  }
  for (const TrolleyTruth& trolley : truth.trolleys) {
    v1::TrolleyGroundTruth* wire = out.add_trolleys();
    wire->set_trolley_id(trolley.trolley_id);
    *wire->mutable_pose() = ToProto(trolley.pose);
    wire->set_carrier_robot_id(trolley.carrier_robot_id);
  }
  for (const SimContact& contact : truth.contacts) {
    v1::Contact* wire = out.add_contacts();
    wire->set_robot_id(contact.robot_id);
    wire->set_other(contact.other);
    wire->set_sim_time_ns(contact.sim_time_ns);
  }
  out.set_min_separation_m(std::isfinite(truth.min_separation_m) ? truth.min_separation_m : 1e9);
  return out;
}

v1::InjectFaultRequest ToProto(const FaultSpec& fault) {
  v1::InjectFaultRequest out;
  for (const FaultTypePair& pair : kFaultTypes) {
    if (pair.type == fault.type) out.set_type(pair.wire);
  }
  *out.mutable_region_min() = ToProto(fault.region_min_m);
  *out.mutable_region_max() = ToProto(fault.region_max_m);
  out.set_robot_id(fault.robot_id);
  out.set_sensor_name(fault.sensor_name);
  out.set_duration_s(fault.duration_s);
  out.set_factor(fault.factor);
  return out;
}

absl::StatusOr<FaultSpec> FromProto(const v1::InjectFaultRequest& request) {
  FaultSpec fault;
  bool known = false;
  for (const FaultTypePair& pair : kFaultTypes) {
    if (pair.wire == request.type()) {
      fault.type = pair.type;
      known = true;
    }
  }
  if (!known) {
    return absl::InvalidArgumentError(
        absl::StrCat("type: unknown or unspecified fault type ", static_cast<int>(request.type())));
  }
  ASSIGN_OR_RETURN(fault.region_min_m, FromProto(request.region_min(), "region_min"));
  ASSIGN_OR_RETURN(fault.region_max_m, FromProto(request.region_max(), "region_max"));
  fault.robot_id = request.robot_id();
  fault.sensor_name = request.sensor_name();
  fault.duration_s = request.duration_s();
  // proto3 has no presence for doubles: an unset factor (0) means "no factor given".
  fault.factor = request.factor();
  if (fault.type == FaultType::kWheelSlipRegion && request.factor() == 0.0) {
    return absl::InvalidArgumentError(
        "factor: wheel slip needs the share of traction kept, in (0, 1]");
  }
  if (fault.factor == 0.0 && fault.type != FaultType::kSlowDown) fault.factor = 1.0;
  return fault;
}

}  // namespace fleetnav
