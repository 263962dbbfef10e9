#include "fleetnav/robot_agent/route_executor.hpp"

#include "absl/strings/str_cat.h"

namespace fleetnav::agent {

RouteExecutor::RouteExecutor(Route route, MotionProfile profile)
    : route_(std::move(route)), profile_(profile) {}

absl::Status RouteExecutor::StartAction(int index) {
  index_ = index;
  const RouteAction& action = route_.actions[index];
  if (action.end.kind != EndConditionKind::kDistance) {
    return absl::FailedPreconditionError(
        absl::StrCat("actions[", index, "] (", std::string(ActionTypeName(action.params)),
                     "): end condition '", std::string(EndConditionKindName(action.end.kind)),
                     "' needs sensing this agent version does not have"));
  }
  if (const auto* straight = std::get_if<StraightAction>(&action.params)) {
    controller_.emplace<StraightController>(straight->distance_m, straight->speed_mps, profile_);
    return absl::OkStatus();
  }
  if (const auto* turn = std::get_if<TurnAction>(&action.params)) {
    controller_.emplace<TurnController>(turn->angle_rad, turn->yaw_rate_radps, profile_);
    return absl::OkStatus();
  }
  return absl::FailedPreconditionError(absl::StrCat("actions[", index, "] (",
                                                    std::string(ActionTypeName(action.params)),
                                                    "): not supported by this agent version"));
}

ExecutorOutput RouteExecutor::Step(const Pose2& pose_in_odom, double dt_s) {
  ExecutorOutput out;
  out.state = state_;
  if (state_ != ExecutionState::kRunning) {
    out.progress_fraction = state_ == ExecutionState::kSucceeded ? 1.0 : 0.0;
    return out;
  }
  if (index_ < 0) {
    if (route_.actions.empty()) {
      state_ = ExecutionState::kSucceeded;
      out.state = state_;
      out.progress_fraction = 1.0;
      return out;
    }
    failure_ = StartAction(0);
  }
  while (failure_.ok()) {
    ControlOutput control;
    if (auto* straight = std::get_if<StraightController>(&controller_)) {
      control = straight->Step(pose_in_odom, dt_s);
      out.mode = NavigationMode::kStraight;
    } else if (auto* turn = std::get_if<TurnController>(&controller_)) {
      control = turn->Step(pose_in_odom, dt_s);
      out.mode = NavigationMode::kTurn;
    }
    const double actions = static_cast<double>(route_.actions.size());
    out.action_index = index_;
    out.progress_fraction = (index_ + control.progress_fraction) / actions;
    if (!control.done) {
      out.command = control.command;
      return out;
    }
    if (index_ + 1 >= static_cast<int>(route_.actions.size())) {
      state_ = ExecutionState::kSucceeded;
      out.state = state_;
      out.mode = NavigationMode::kIdle;
      out.progress_fraction = 1.0;
      out.command = Twist2{};
      return out;
    }
    failure_ = StartAction(index_ + 1);
  }
  state_ = ExecutionState::kFailed;
  out.state = state_;
  out.mode = NavigationMode::kFault;
  out.command = Twist2{};
  return out;
}

}  // namespace fleetnav::agent
