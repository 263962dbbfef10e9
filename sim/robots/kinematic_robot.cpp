#include "fleetnav/sim/kinematic_robot.hpp"

#include <algorithm>
#include <cmath>

#include "fleetnav/core/rate_limit.hpp"
#include "fleetnav/sim/ackermann_steering.hpp"

namespace fleetnav::sim {
namespace {

constexpr double kGroundClearanceM = 0.02;

// Pose after moving with a body twist for dt (translation at the mid-interval heading).
Pose2 Integrate(const Pose2& pose, double vx, double vy, double yaw_rate, double dt) {
  const double dtheta = yaw_rate * dt;
  const double mid = pose.yaw_rad() + 0.5 * dtheta;
  const double c = std::cos(mid), s = std::sin(mid);
  return Pose2(pose.x_m() + (c * vx - s * vy) * dt, pose.y_m() + (s * vx + c * vy) * dt,
               pose.yaw_rad() + dtheta);
}

}  // namespace

KinematicRobot::KinematicRobot(OdeWorld* world, int robot_index, const RobotModel& model,
                               const Pose2& start)
    : model_(model), pose_(start) {
  const Eigen::AlignedBox2d box = model.FootprintBounds();
  body_ = dBodyCreate(world->world());
  dBodySetKinematic(body_);
  dGeomID geom = dCreateBox(world->space(), box.sizes().x(), box.sizes().y(), model.height_m);
  dGeomSetBody(geom, body_);
  dGeomSetOffsetPosition(geom, box.center().x(), box.center().y(), 0.0);
  dGeomSetData(geom, world->MakeTag(GeomRole::kChassis, robot_index));
  PlaceBody();
}

void KinematicRobot::PlaceBody() {
  dBodySetPosition(body_, pose_.x_m(), pose_.y_m(), kGroundClearanceM + 0.5 * model_.height_m);
  dMatrix3 rotation;
  dRFromAxisAndAngle(rotation, 0, 0, 1, pose_.yaw_rad());
  dBodySetRotation(body_, rotation);
  dBodySetLinearVel(body_, 0, 0, 0);
  dBodySetAngularVel(body_, 0, 0, 0);
}

absl::Status KinematicRobot::SetDrive(const DriveCommand& drive, double scale) {
  const MotionLimits& limits = model_.limits;
  if (model_.kinematics == Kinematics::kOmnidirectional) {
    const auto* twist = std::get_if<Twist2>(&drive);
    if (twist == nullptr) {
      return absl::InvalidArgumentError("the robot is omnidirectional: send a twist");
    }
    target_ = ClampOmniTwist(limits, *twist, scale);
    return absl::OkStatus();
  }
  absl::StatusOr<AckermannTarget> target =
      AckermannTargetOf(model_, drive, scale, target_steering_rad_);
  if (!target.ok()) return target.status();
  target_speed_mps_ = target->speed_mps;
  target_steering_rad_ = target->steering_rad;
  return absl::OkStatus();
}

Pose2 KinematicRobot::Propose(double dt, double traction) {
  const MotionLimits& limits = model_.limits;
  proposed_wheels_ = wheel_angles_;
  if (model_.kinematics == Kinematics::kOmnidirectional) {
    Twist2 v;
    v.vx_mps = StepTowards(command_velocity_.vx_mps, target_.vx_mps, limits.max_accel_mps2 * dt);
    v.vy_mps = StepTowards(command_velocity_.vy_mps, target_.vy_mps, limits.max_accel_mps2 * dt);
    v.yaw_rate_radps = StepTowards(command_velocity_.yaw_rate_radps, target_.yaw_rate_radps,
                                   limits.max_yaw_accel_radps2 * dt);
    proposed_command_velocity_ = v;
    const MecanumWheelRates rates = MecanumInverse(model_, v);
    for (size_t i = 0; i < 4; ++i) proposed_wheels_[i] += rates[i] * dt;

    proposed_velocity_ =
        Twist2{traction * v.vx_mps, traction * v.vy_mps, traction * v.yaw_rate_radps};
    proposed_pose_ = Integrate(pose_, proposed_velocity_.vx_mps, proposed_velocity_.vy_mps,
                               proposed_velocity_.yaw_rate_radps, dt);
    return proposed_pose_;
  }
  // Ackermann bicycle model about the rear axle.
  proposed_steering_rad_ = std::clamp(
      StepTowards(steering_rad_, target_steering_rad_, limits.max_steering_rate_radps * dt),
      -limits.max_steering_rad, limits.max_steering_rad);
  proposed_speed_mps_ = StepTowards(speed_mps_, target_speed_mps_, limits.max_accel_mps2 * dt);
  const double yaw_rate =
      proposed_speed_mps_ * std::tan(proposed_steering_rad_) / model_.wheelbase_m;
  const double half_track = 0.5 * model_.track_m;
  proposed_wheels_[0] += (proposed_speed_mps_ - yaw_rate * half_track) / model_.wheel_radius_m * dt;
  proposed_wheels_[1] += (proposed_speed_mps_ + yaw_rate * half_track) / model_.wheel_radius_m * dt;
  proposed_velocity_ = Twist2{traction * proposed_speed_mps_, 0.0, traction * yaw_rate};
  proposed_pose_ =
      Integrate(pose_, proposed_velocity_.vx_mps, 0.0, proposed_velocity_.yaw_rate_radps, dt);
  return proposed_pose_;
}

void KinematicRobot::Commit(bool blocked) {
  if (blocked) {
    velocity_ = Twist2{};
    command_velocity_ = Twist2{};
    speed_mps_ = 0.0;
    steering_rad_ = proposed_steering_rad_;
  } else {
    pose_ = proposed_pose_;
    velocity_ = proposed_velocity_;
    command_velocity_ = proposed_command_velocity_;
    wheel_angles_ = proposed_wheels_;
    steering_rad_ = proposed_steering_rad_;
    speed_mps_ = proposed_speed_mps_;
  }
  PlaceBody();
}

std::vector<WheelAngle> KinematicRobot::WheelAngles() const {
  if (model_.kinematics == Kinematics::kOmnidirectional) {
    return {{"front_left", wheel_angles_[0]},
            {"front_right", wheel_angles_[1]},
            {"rear_left", wheel_angles_[2]},
            {"rear_right", wheel_angles_[3]}};
  }
  return {{"left", wheel_angles_[0]}, {"right", wheel_angles_[1]}};
}

}  // namespace fleetnav::sim
