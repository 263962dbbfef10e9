#pragma once

#include <memory>
#include <string>
#include <variant>

#include "absl/status/status.h"
#include "fleetnav/core/route.hpp"
#include "fleetnav/robot_agent/motion_controllers.hpp"

namespace fleetnav::agent {

enum class ExecutionState { kRunning, kSucceeded, kFailed };

/// What the executor asks of the drive this tick, and where it stands.
struct ExecutorOutput {
  Twist2 command;
  NavigationMode mode = NavigationMode::kIdle;
  int action_index = -1;
  double progress_fraction = 0.0;  ///< of the whole route
  ExecutionState state = ExecutionState::kRunning;
};

/// Runs a route's actions one after another on odometry (Lely thesis §6.3): each action gets
/// its controller when it starts and hands over when its end condition holds. This version
/// executes turn and straight actions ended by distance; any other action fails the route
/// with a reason naming the action's index (FailedPrecondition), so nothing is silently
/// skipped. Not thread-safe.
class RouteExecutor {
 public:
  RouteExecutor(Route route, MotionProfile profile = {});

  ExecutorOutput Step(const Pose2& pose_in_odom, double dt_s);
  ExecutionState state() const { return state_; }
  /// Why the route failed (OK while running or after success).
  const absl::Status& failure() const { return failure_; }
  const Route& route() const { return route_; }

 private:
  absl::Status StartAction(int index);

  Route route_;
  MotionProfile profile_;
  int index_ = -1;
  std::variant<std::monostate, StraightController, TurnController> controller_;
  ExecutionState state_ = ExecutionState::kRunning;
  absl::Status failure_;
};

}  // namespace fleetnav::agent
