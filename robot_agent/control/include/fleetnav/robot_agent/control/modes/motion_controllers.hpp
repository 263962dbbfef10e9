#pragma once

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/robot_agent/control/common/motion_controller.hpp"

namespace fleetnav::agent {

/// Limits shared by the reactive motion controllers.
struct MotionProfile {
  double accel_mps2 = 0.3;
  double decel_mps2 = 0.3;
  double yaw_accel_radps2 = 0.6;
  double min_speed_mps = 0.02;  ///< creep speed near the end so the goal is reached
  double min_yaw_rate_radps = 0.02;
  absl::Status Validate() const;

  /// The next speed of a trapezoidal profile towards `target_mps` that stops exactly after
  /// `remaining_m` (v ≤ √(2·decel·remaining)), never below the creep speed so the end is reached.
  double NextSpeed(double target_mps, double last_mps, double remaining_m, double dt_s) const;
};

struct HeadingPidGains {
  double kp = 2.0;
  double ki = 0.1;
  double kd = 0.05;
  double cross_track_gain = 0.8;  ///< rad/s per metre of lateral offset
  absl::Status Validate() const;
};

/// Drives straight ahead for a distance holding the heading it started with (Lely thesis
/// §6.3, "straight driving": PID on the heading), with a trapezoidal speed profile that ends
/// exactly at the distance (v ≤ √(2·a·remaining)) and a cross-track term that pulls back onto
/// the start line. Drives on the odometry pose, which never jumps. Not thread-safe.
class StraightController : public MotionController {
 public:
  StraightController(double distance_m, double speed_mps, MotionProfile profile,
                     HeadingPidGains gains = {});
  ControlOutput Step(const ControlInput& input) override;

 private:
  double distance_m_;
  double speed_mps_;
  MotionProfile profile_;
  HeadingPidGains gains_;
  bool started_ = false;
  Pose2 start_;
  double last_speed_mps_ = 0.0;
  double integral_ = 0.0;
  double last_error_ = 0.0;
};

/// Turns in place by an angle (Lely thesis §6.3, "turn": until the orientation difference
/// reaches the angle), with a yaw-rate profile that lands on the target (ω ≤ √(2·α·|error|)).
/// Turns on the odometry pose (gyro-aided). Not thread-safe.
class TurnController : public MotionController {
 public:
  TurnController(double angle_rad, double yaw_rate_radps, MotionProfile profile,
                 double tolerance_rad = 0.003);
  ControlOutput Step(const ControlInput& input) override;

 private:
  double angle_rad_;
  double yaw_rate_radps_;
  MotionProfile profile_;
  double tolerance_rad_;
  bool started_ = false;
  double last_yaw_rad_ = 0.0;
  double turned_rad_ = 0.0;
  double last_rate_radps_ = 0.0;
};

}  // namespace fleetnav::agent
