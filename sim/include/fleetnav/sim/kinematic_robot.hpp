#pragma once

#include <ode/ode.h>

#include <array>
#include <cstdint>
#include <string>

#include "fleetnav/sim/mecanum_kinematics.hpp"
#include "fleetnav/sim/ode_world.hpp"
#include "fleetnav/sim/robot_body.hpp"

namespace fleetnav::sim {

/// A robot moved kinematically: the omni platform (mecanum) and the Ackermann delivery robot
/// (bicycle model with steering angle and rate limits). Commands are clamped to the model's
/// limits and followed with its acceleration limits; encoders come from the wheel rates the
/// motion implies. The body is also an ODE kinematic body so that physical robots collide with
/// it. The simulation proposes each tick's motion (Propose), checks it for collisions and
/// commits or blocks it (Commit). Not thread-safe.
class KinematicRobot final : public RobotBody {
 public:
  KinematicRobot(OdeWorld* world, int robot_index, const RobotModel& model, const Pose2& start);

  absl::Status SetDrive(const DriveCommand& drive, double scale) override;
  void AfterStep(double, double) override {}
  /// The pose after `period_s` at the commanded motion; wheels turn as commanded, the ground
  /// moves `traction` times as far.
  Pose2 Propose(double period_s, double traction);
  /// Takes the proposed motion, or (blocked) stays and stops.
  void Commit(bool blocked);

  Pose2 GroundTruthPose() const override { return pose_; }
  Twist2 GroundTruthVelocity() const override { return velocity_; }
  double yaw_rate_radps() const override { return velocity_.yaw_rate_radps; }
  const RobotModel& model() const override { return model_; }
  std::vector<WheelAngle> WheelAngles() const override;
  bool physical() const override { return false; }
  std::optional<double> SteeringAngleRad() const override {
    if (model_.kinematics != Kinematics::kAckermann) return std::nullopt;
    return steering_rad_;
  }
  dBodyID chassis_body() const override { return body_; }

 private:
  void PlaceBody();

  RobotModel model_;
  dBodyID body_ = nullptr;
  Pose2 pose_;
  Twist2 velocity_;                   ///< actual body twist (ground)
  Twist2 target_;                     ///< omni: commanded twist
  Twist2 command_velocity_;           ///< omni: the twist the wheels drive (before slip)
  double target_speed_mps_ = 0.0;     ///< Ackermann
  double target_steering_rad_ = 0.0;  ///< Ackermann
  double steering_rad_ = 0.0;
  double speed_mps_ = 0.0;
  std::array<double, 4> wheel_angles_{};
  // Proposal of the current tick.
  Pose2 proposed_pose_;
  Twist2 proposed_velocity_;
  Twist2 proposed_command_velocity_;
  std::array<double, 4> proposed_wheels_{};
  double proposed_steering_rad_ = 0.0;
  double proposed_speed_mps_ = 0.0;
};

}  // namespace fleetnav::sim
