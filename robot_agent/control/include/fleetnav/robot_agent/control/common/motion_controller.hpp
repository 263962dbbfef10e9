#pragma once

#include <optional>
#include <string>

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/robot_agent/perception.hpp"

namespace fleetnav::agent {

/// What a controller sees each control tick: the localizer's pose in map, the continuous
/// odometry pose, the measured body twist and the tick's perception.
struct ControlInput {
  Pose2 pose_in_map;
  Pose2 pose_in_odom;
  Twist2 velocity;
  Perception perception;
  double dt_s = 0.0;
};

/// One control step's answer: the twist to drive, whether the action's own end condition
/// holds, the action's progress, the navigation mode the controller is in, and — when not OK —
/// why the action cannot go on (the executor fails the route with it).
struct ControlOutput {
  Twist2 command;
  bool done = false;
  double progress_fraction = 0.0;
  NavigationMode mode = NavigationMode::kIdle;
  /// Set on the tick the controller switches between reactive and map-based: why.
  std::string mode_reason;
  absl::Status failure;
  /// Set: where the lift must go (raised latches the trolley above); unset: it stays.
  std::optional<bool> lift_raised;
};

/// One navigation mode of the hybrid controller (Lely thesis §6.6, Fig. 6.12): turn, straight,
/// fence following, … . A controller is made when its action starts and stepped once per
/// control tick until it reports done (or a failure). Not thread-safe.
class MotionController {
 public:
  virtual ~MotionController() = default;
  virtual ControlOutput Step(const ControlInput& input) = 0;
  /// How far the robot drives along the path it follows before it stands just short of
  /// `gate` (PathDistanceToGate); nullopt for a mode without a planned path, or when the path
  /// does not come to the gate.
  virtual std::optional<double> PathDistanceToGate(const Pose2& /*gate*/) const {
    return std::nullopt;
  }
};

/// A ControlInput carrying only the odometry pose (for controllers that drive on odometry).
inline ControlInput OdometryInput(const Pose2& pose_in_odom, double dt_s) {
  ControlInput input;
  input.pose_in_map = pose_in_odom;
  input.pose_in_odom = pose_in_odom;
  input.dt_s = dt_s;
  return input;
}

}  // namespace fleetnav::agent
