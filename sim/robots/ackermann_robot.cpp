#include "fleetnav/sim/ackermann_robot.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/rate_limit.hpp"
#include "fleetnav/sim/ackermann_steering.hpp"

namespace fleetnav::sim {
namespace {

constexpr double kGravityMps2 = 9.81;

}  // namespace

absl::Status AckermannBodyParams::Validate() const {
  for (auto [name, value] : {std::pair{"max_wheel_torque_nm", max_wheel_torque_nm},
                             {"tyre_grip_mu", tyre_grip_mu},
                             {"suspension_spring_npm", suspension_spring_npm},
                             {"mass_box_height_m", mass_box_height_m}}) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      return absl::InvalidArgumentError(absl::StrCat(name, ": must be finite and > 0"));
    }
  }
  for (auto [name, value] : {std::pair{"rolling_resistance_mu", rolling_resistance_mu},
                             {"tyre_creep_mps_per_n", tyre_creep_mps_per_n},
                             {"suspension_damper_nspm", suspension_damper_nspm},
                             {"ground_clearance_m", ground_clearance_m}}) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      return absl::InvalidArgumentError(absl::StrCat(name, ": must be finite and >= 0"));
    }
  }
  return absl::OkStatus();
}

AckermannRobot::AckermannRobot(OdeWorld* world, int robot_index, const RobotModel& model,
                               const Pose2& start, AckermannBodyParams params)
    : model_(model), params_(params) {
  const Eigen::AlignedBox2d bounds = model.FootprintBounds();
  const Eigen::Vector2d size = bounds.sizes();
  // The centre of mass midway between the axles: the wheels share the load evenly.
  base_x_in_chassis_m_ = -0.5 * model.wheelbase_m;
  // Each wheel carries a quarter of the weight, pressed that far into its sprung contact.
  const double wheel_load_n = 0.25 * model.mass_kg * kGravityMps2;
  const double sink_m = wheel_load_n / params_.suspension_spring_npm;
  chassis_z_m_ = model.wheel_radius_m - sink_m + 0.5 * params_.mass_box_height_m;

  chassis_ = dBodyCreate(world->world());
  dMass mass;
  dMassSetBoxTotal(&mass, model.mass_kg, size.x(), size.y(), params_.mass_box_height_m);
  dBodySetMass(chassis_, &mass);
  const Eigen::Vector2d centre = start.TransformPoint(Eigen::Vector2d(0.5 * model.wheelbase_m, 0));
  dBodySetPosition(chassis_, centre.x(), centre.y(), chassis_z_m_);
  dMatrix3 rotation;
  dRFromAxisAndAngle(rotation, 0, 0, 1, start.yaw_rad());
  dBodySetRotation(chassis_, rotation);

  // Collision box: the whole body, from the clearance up, around the footprint.
  dGeomID box = dCreateBox(world->space(), size.x(), size.y(), model.height_m);
  dGeomSetBody(box, chassis_);
  const Eigen::Vector2d box_centre = bounds.center();
  dGeomSetOffsetPosition(box, box_centre.x() + base_x_in_chassis_m_, box_centre.y(),
                         params_.ground_clearance_m + 0.5 * model.height_m - chassis_z_m_);
  dGeomSetData(box, world->MakeTag(GeomRole::kChassis, robot_index));

  // The wheels: a floor contact under each hub (a sphere of the wheel's radius).
  const double hub_z = model.wheel_radius_m - chassis_z_m_;
  const double motor_mu = params_.max_wheel_torque_nm / (model.wheel_radius_m * wheel_load_n);
  const auto make_wheel = [&](double x_in_base, double y) {
    dGeomID geom = dCreateSphere(world->space(), model.wheel_radius_m);
    dGeomSetBody(geom, chassis_);
    dGeomSetOffsetPosition(geom, x_in_base + base_x_in_chassis_m_, y, hub_z);
    GeomTag* tag = world->MakeTag(GeomRole::kWheel, robot_index);
    tag->contact_spring_npm = params_.suspension_spring_npm;
    tag->contact_damper_nspm = params_.suspension_damper_nspm;
    dGeomSetData(geom, tag);
    return tag;
  };
  const double half_track = 0.5 * model.track_m;
  for (size_t side = 0; side < 2; ++side) {
    const double y = side == 0 ? half_track : -half_track;
    rear_tags_[side] = make_wheel(0.0, y);
    // Driven: grips along its plane up to what the motor's torque pushes with, and across.
    rear_tags_[side]->friction = {chassis_,
                                  1.0,
                                  0.0,
                                  std::min(params_.tyre_grip_mu, motor_mu),
                                  params_.tyre_grip_mu,
                                  params_.tyre_creep_mps_per_n};
    front_tags_[side] = make_wheel(model.wheelbase_m, y);
    // Free-rolling: rolling resistance along its plane, grip across it.
    front_tags_[side]->friction = {chassis_,
                                   1.0,
                                   0.0,
                                   params_.rolling_resistance_mu,
                                   params_.tyre_grip_mu,
                                   params_.tyre_creep_mps_per_n};
  }
}

absl::Status AckermannRobot::SetDrive(const DriveCommand& drive, double scale) {
  absl::StatusOr<AckermannTarget> target =
      AckermannTargetOf(model_, drive, scale, target_steering_rad_);
  if (!target.ok()) return target.status();
  target_speed_mps_ = target->speed_mps;
  target_steering_rad_ = target->steering_rad;
  dBodyEnable(chassis_);
  return absl::OkStatus();
}

void AckermannRobot::SetWheels() {
  const FrontWheelAngles angles =
      AckermannFrontWheelAngles(steering_rad_, model_.wheelbase_m, model_.track_m);
  const std::array<double, 2> front = {angles.left_rad, angles.right_rad};
  for (size_t side = 0; side < 2; ++side) {
    front_tags_[side]->friction.axis_x = std::cos(front[side]);
    front_tags_[side]->friction.axis_y = std::sin(front[side]);
  }
  // Electronic differential: each rear wheel at the speed of its own arc.
  const double curvature = std::tan(steering_rad_) / model_.wheelbase_m;
  const double half_track = 0.5 * model_.track_m;
  const std::array<double, 2> rim_mps = {speed_mps_ * (1.0 - half_track * curvature),
                                         speed_mps_ * (1.0 + half_track * curvature)};
  for (size_t side = 0; side < 2; ++side) {
    rear_rates_radps_[side] = rim_mps[side] / model_.wheel_radius_m;
    rear_tags_[side]->friction.surface_speed_mps = rim_mps[side];
  }
}

void AckermannRobot::AfterStep(double step_s, double traction) {
  const MotionLimits& limits = model_.limits;
  steering_rad_ = std::clamp(
      StepTowards(steering_rad_, target_steering_rad_, limits.max_steering_rate_radps * step_s),
      -limits.max_steering_rad, limits.max_steering_rad);
  speed_mps_ = StepTowards(speed_mps_, target_speed_mps_, limits.max_accel_mps2 * step_s);
  SetWheels();
  // The velocity-controlled motors turn at their rates (the ground, not the motor, gives way).
  const double spin = traction > 0.0 ? 1.0 / traction : 1.0;
  for (size_t side = 0; side < 2; ++side) {
    rear_angles_rad_[side] += rear_rates_radps_[side] * step_s * spin;
  }
}

Pose2 AckermannRobot::GroundTruthPose() const {
  const dReal* r = dBodyGetRotation(chassis_);  // row-major 3x4
  const dReal* p = dBodyGetPosition(chassis_);
  const Pose2 chassis(p[0], p[1], std::atan2(r[4], r[0]));
  return chassis * Pose2(base_x_in_chassis_m_, 0.0, 0.0);
}

Twist2 AckermannRobot::GroundTruthVelocity() const {
  dVector3 world_velocity, velocity;
  dBodyGetRelPointVel(chassis_, base_x_in_chassis_m_, 0.0, 0.0, world_velocity);
  dBodyVectorFromWorld(chassis_, world_velocity[0], world_velocity[1], world_velocity[2], velocity);
  return Twist2{velocity[0], velocity[1], yaw_rate_radps()};
}

double AckermannRobot::UpVectorZ() const { return dBodyGetRotation(chassis_)[10]; }

double AckermannRobot::yaw_rate_radps() const { return dBodyGetAngularVel(chassis_)[2]; }

std::vector<WheelAngle> AckermannRobot::WheelAngles() const {
  return {{"left", rear_angles_rad_[0]}, {"right", rear_angles_rad_[1]}};
}

}  // namespace fleetnav::sim
