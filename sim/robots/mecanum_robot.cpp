#include "fleetnav/sim/mecanum_robot.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/rate_limit.hpp"

namespace fleetnav::sim {
namespace {

constexpr double kRollerComponent = M_SQRT1_2;  // rollers at 45°

/// Wheels in MecanumWheelRates order, with the direction their rollers grip along (in the
/// chassis frame): a wheel's rim speed is the hub's velocity along that axis, scaled.
struct WheelLayout {
  double x_sign, y_sign, roller_x, roller_y;
};
constexpr std::array<WheelLayout, 4> kWheels = {{
    {1, 1, kRollerComponent, -kRollerComponent},   // front-left
    {1, -1, kRollerComponent, kRollerComponent},   // front-right
    {-1, 1, kRollerComponent, kRollerComponent},   // rear-left
    {-1, -1, kRollerComponent, -kRollerComponent}  // rear-right
}};
constexpr std::array<const char*, 4> kWheelNames = {"front_left", "front_right", "rear_left",
                                                    "rear_right"};

void PlaceAt(dBodyID body, const Pose2& start, const Eigen::Vector2d& at, double z) {
  const Eigen::Vector2d p = start.TransformPoint(at);
  dBodySetPosition(body, p.x(), p.y(), z);
}

void SetYaw(dBodyID body, double yaw_rad) {
  dMatrix3 rotation;
  dRFromAxisAndAngle(rotation, 0, 0, 1, yaw_rad);
  dBodySetRotation(body, rotation);
}

}  // namespace

absl::Status MecanumBodyParams::Validate() const {
  for (auto [name, value] : {std::pair{"max_wheel_torque_nm", max_wheel_torque_nm},
                             {"roller_grip_mu", roller_grip_mu},
                             {"suspension_spring_npm", suspension_spring_npm},
                             {"caster_radius_m", caster_radius_m},
                             {"caster_trail_m", caster_trail_m},
                             {"mass_box_height_m", mass_box_height_m}}) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      return absl::InvalidArgumentError(absl::StrCat(name, ": must be finite and > 0"));
    }
  }
  for (auto [name, value] : {std::pair{"roller_free_mu", roller_free_mu},
                             {"suspension_damper_nspm", suspension_damper_nspm},
                             {"suspension_preload_m", suspension_preload_m},
                             {"caster_rolling_mu", caster_rolling_mu},
                             {"swivel_friction_nm", swivel_friction_nm},
                             {"roller_creep_mps_per_n", roller_creep_mps_per_n},
                             {"swivel_noise_rad_per_sqrt_s", swivel_noise_rad_per_sqrt_s},
                             {"ground_clearance_m", ground_clearance_m}}) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      return absl::InvalidArgumentError(absl::StrCat(name, ": must be finite and >= 0"));
    }
  }
  return absl::OkStatus();
}

MecanumRobot::MecanumRobot(OdeWorld* world, int robot_index, const RobotModel& model,
                           const Pose2& start, uint64_t noise_seed, MecanumBodyParams params)
    : model_(model),
      params_(params),
      world_(world),
      robot_index_(robot_index),
      swivel_noise_(noise_seed) {
  const Eigen::AlignedBox2d bounds = model.FootprintBounds();
  const Eigen::Vector2d size = bounds.sizes();
  const double chassis_z = params_.ground_clearance_m + 0.5 * params_.mass_box_height_m;

  chassis_ = dBodyCreate(world->world());
  dMass mass;
  const double chassis_kg = model.mass_kg;
  dMassSetBoxTotal(&mass, chassis_kg, size.x(), size.y(), params_.mass_box_height_m);
  dBodySetMass(chassis_, &mass);
  PlaceAt(chassis_, start, Eigen::Vector2d::Zero(), chassis_z);
  SetYaw(chassis_, start.yaw_rad());
  // Collision box: the whole body, from the clearance up, around the footprint.
  dGeomID box = dCreateBox(world->space(), size.x(), size.y(), model.height_m);
  dGeomSetBody(box, chassis_);
  const Eigen::Vector2d center = bounds.center();
  dGeomSetOffsetPosition(box, center.x(), center.y(),
                         params_.ground_clearance_m + 0.5 * model.height_m - chassis_z);
  dGeomSetData(box, world->MakeTag(GeomRole::kChassis, robot_index));

  // The axles sit the suspension's preload lower than the wheel radius: the wheels press into
  // the floor by that much, and the sprung contact pushes each up with about spring × preload.
  const double axle_z = model.wheel_radius_m - params_.suspension_preload_m;
  for (size_t i = 0; i < 4; ++i) {
    const WheelLayout& w = kWheels[i];
    const Eigen::Vector2d at(w.x_sign * 0.5 * model.wheelbase_m, w.y_sign * 0.5 * model.track_m);
    wheel_tags_[i] = CreateWheel(at, axle_z - chassis_z, w.roller_x, w.roller_y);
    // Casters start trailing forward motion; the contact is a frictionless sphere of the
    // chassis (the caster's own forces come from StepCaster).
    swivel_axes_m_[i] =
        Eigen::Vector2d(w.x_sign * params_.caster_x_m, w.y_sign * params_.caster_y_m);
    caster_geoms_[i] = dCreateSphere(world->space(), params_.caster_radius_m);
    dGeomSetBody(caster_geoms_[i], chassis_);
    dGeomSetData(caster_geoms_[i], world->MakeTag(GeomRole::kCaster, robot_index));
  }
  caster_z_in_chassis_m_ = params_.caster_radius_m - chassis_z;
  const double wheel_load_n = params_.suspension_spring_npm * params_.suspension_preload_m;
  caster_load_n_ = std::max(0.0, 0.25 * (model.mass_kg * 9.81 - 4 * wheel_load_n));
  for (size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d contact = swivel_axes_m_[i] - Eigen::Vector2d(params_.caster_trail_m, 0);
    dGeomSetOffsetPosition(caster_geoms_[i], contact.x(), contact.y(), caster_z_in_chassis_m_);
  }
}

GeomTag* MecanumRobot::CreateWheel(const Eigen::Vector2d& at, double axle_z_in_chassis_m,
                                   double roller_x, double roller_y) {
  // One contact point under the hub (a sphere of the wheel's radius on the chassis), whose
  // surface moves at the rim speed along the roller axis.
  dGeomID geom = dCreateSphere(world_->space(), model_.wheel_radius_m);
  dGeomSetBody(geom, chassis_);
  dGeomSetOffsetPosition(geom, at.x(), at.y(), axle_z_in_chassis_m);
  GeomTag* tag = world_->MakeTag(GeomRole::kWheel, robot_index_);
  // The motor's torque limit caps the force the wheel can push with, below the floor's grip.
  const double load_n = params_.suspension_spring_npm * params_.suspension_preload_m;
  const double motor_mu = params_.max_wheel_torque_nm / (model_.wheel_radius_m * load_n);
  tag->friction = {chassis_,
                   roller_x,
                   roller_y,
                   std::min(params_.roller_grip_mu, motor_mu),
                   params_.roller_free_mu,
                   params_.roller_creep_mps_per_n};
  tag->contact_spring_npm = params_.suspension_spring_npm;
  tag->contact_damper_nspm = params_.suspension_damper_nspm;
  dGeomSetData(geom, tag);
  return tag;
}

absl::Status MecanumRobot::SetDrive(const DriveCommand& drive, double scale) {
  const auto* twist = std::get_if<Twist2>(&drive);
  if (twist == nullptr) {
    return absl::InvalidArgumentError("the robot is omnidirectional: send a twist");
  }
  if (!std::isfinite(twist->vx_mps) || !std::isfinite(twist->vy_mps) ||
      !std::isfinite(twist->yaw_rate_radps)) {
    return absl::InvalidArgumentError("twist: not finite");
  }
  target_ = ClampOmniTwist(model_.limits, *twist, scale);
  dBodyEnable(chassis_);
  return absl::OkStatus();
}

void MecanumRobot::SetWheelRates(const MecanumWheelRates& rates) {
  for (size_t i = 0; i < 4; ++i) {
    // The hub moves at r·q along base_link x relative to the rim's contact point; the contact
    // grips the part of that along the rollers.
    wheel_rates_radps_[i] = rates[i];
    wheel_tags_[i]->friction.surface_speed_mps =
        model_.wheel_radius_m * rates[i] * kWheels[i].roller_x;
  }
}

void MecanumRobot::AfterStep(double step_s, double traction) {
  const MotionLimits& limits = model_.limits;
  ramped_.vx_mps = StepTowards(ramped_.vx_mps, target_.vx_mps, limits.max_accel_mps2 * step_s);
  ramped_.vy_mps = StepTowards(ramped_.vy_mps, target_.vy_mps, limits.max_accel_mps2 * step_s);
  ramped_.yaw_rate_radps = StepTowards(ramped_.yaw_rate_radps, target_.yaw_rate_radps,
                                       limits.max_yaw_accel_radps2 * step_s);
  SetWheelRates(MecanumInverse(model_, ramped_));
  const double spin = traction > 0.0 ? 1.0 / traction : 1.0;
  for (size_t i = 0; i < 4; ++i) {
    // The velocity-controlled motor turns at its rate (the floor's grip, not the motor, gives
    // way first).
    wheel_angles_rad_[i] += wheel_rates_radps_[i] * step_s * spin;
    StepCaster(i, step_s);
  }
}

void MecanumRobot::StepCaster(size_t i, double step_s) {
  const double trail = params_.caster_trail_m;
  const double angle = swivel_turned_rad_[i];
  const Eigen::Vector2d along(std::cos(angle), std::sin(angle));  // contact -> swivel axis
  const Eigen::Vector2d side(-along.y(), along.x());
  const Eigen::Vector2d contact = swivel_axes_m_[i] - trail * along;
  // The chassis's velocity at the contact, in base_link.
  dVector3 world_velocity, velocity;
  dBodyGetRelPointVel(chassis_, contact.x(), contact.y(), caster_z_in_chassis_m_, world_velocity);
  dBodyVectorFromWorld(chassis_, world_velocity[0], world_velocity[1], world_velocity[2], velocity);
  const Eigen::Vector2d v(velocity[0], velocity[1]);
  // No side slip: the caster turns (relative to the chassis) so that its contact rolls.
  const double swivel_rate = v.dot(side) / trail;
  // Forces of the floor on the platform through the caster (smoothed Coulomb laws).
  constexpr double kSmoothMps = 0.005;
  const double sideways_n =
      -params_.swivel_friction_nm / trail * std::tanh(v.dot(side) / kSmoothMps);
  const double rolling_n =
      -params_.caster_rolling_mu * caster_load_n_ * std::tanh(v.dot(along) / kSmoothMps);
  const Eigen::Vector2d force = sideways_n * side + rolling_n * along;
  dBodyAddRelForceAtRelPos(chassis_, force.x(), force.y(), 0.0, contact.x(), contact.y(),
                           caster_z_in_chassis_m_);
  swivel_turned_rad_[i] +=
      swivel_rate * step_s +
      swivel_noise_.Gaussian(params_.swivel_noise_rad_per_sqrt_s * std::sqrt(step_s));
  const double next = swivel_turned_rad_[i];
  const Eigen::Vector2d next_contact =
      swivel_axes_m_[i] - trail * Eigen::Vector2d(std::cos(next), std::sin(next));
  dGeomSetOffsetPosition(caster_geoms_[i], next_contact.x(), next_contact.y(),
                         caster_z_in_chassis_m_);
}

Pose2 MecanumRobot::GroundTruthPose() const {
  const dReal* r = dBodyGetRotation(chassis_);  // row-major 3x4
  const dReal* p = dBodyGetPosition(chassis_);
  return Pose2(p[0], p[1], std::atan2(r[4], r[0]));
}

Twist2 MecanumRobot::GroundTruthVelocity() const {
  const dReal* v = dBodyGetLinearVel(chassis_);
  const double yaw = GroundTruthPose().yaw_rad();
  const double c = std::cos(yaw), s = std::sin(yaw);
  return Twist2{c * v[0] + s * v[1], -s * v[0] + c * v[1], yaw_rate_radps()};
}

double MecanumRobot::UpVectorZ() const { return dBodyGetRotation(chassis_)[10]; }

double MecanumRobot::yaw_rate_radps() const { return dBodyGetAngularVel(chassis_)[2]; }

std::vector<WheelAngle> MecanumRobot::WheelAngles() const {
  std::vector<WheelAngle> angles;
  for (size_t i = 0; i < 4; ++i) angles.push_back({kWheelNames[i], wheel_angles_rad_[i]});
  return angles;
}

double MecanumRobot::caster_angle_rad(int i) const {
  return std::remainder(swivel_turned_rad_[static_cast<size_t>(i)], 2 * kPi);
}

}  // namespace fleetnav::sim
