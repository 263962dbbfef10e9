#include "fleetnav/robot_agent/route_executor.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/robot_agent/action_remainder.hpp"
#include "fleetnav/robot_agent/route_site_check.hpp"

namespace fleetnav::agent {

RouteExecutor::RouteExecutor(Route route, RouteContext context, ModeParams params,
                             std::optional<Pose2> start_in_map, const RoutePosition& from)
    : route_(std::move(route)),
      context_(std::move(context)),
      params_(params),
      lift_raised_(context_.carried_load_m.has_value()) {
  if (absl::Status s = params_.Validate(); !s.ok()) {
    failure_ = absl::InvalidArgumentError(absl::StrCat("mode parameters: ", s.message()));
  } else {
    failure_ = CheckRoute(route_, context_, params_);
  }
  if (failure_.ok()) failure_ = ResumeAt(from, start_in_map.value_or(Pose2{}));
  if (failure_.ok() && start_in_map.has_value() && state_ == ExecutionState::kRunning) {
    failure_ = CheckRouteOnSite(route_, context_, *start_in_map, {}, index_ + 1);
  }
  if (!failure_.ok()) state_ = ExecutionState::kFailed;
}

absl::Status RouteExecutor::StartAction(int index) {
  if (index != index_) action_fraction_ = 0.0;
  index_ = index;
  absl::StatusOr<std::unique_ptr<MotionController>> controller =
      MakeController(route_.actions[index], index, context_, params_,
                     index > 0 ? &route_.actions[index - 1] : nullptr);
  if (!controller.ok()) return controller.status();
  controller_ = *std::move(controller);
  ++actions_started_;
  return absl::OkStatus();
}

void RouteExecutor::SetActionPath(const ActionPath& path) {
  const int a = path.action_index;
  if (state_ != ExecutionState::kRunning || a < 0 || a >= static_cast<int>(route_.actions.size()) ||
      a < index_ || (a == index_ && (waiting_ || controller_ == nullptr))) {
    return;
  }
  auto* nav = std::get_if<FreeNavigationAction>(&route_.actions[a].params);
  if (nav == nullptr) return;
  auto [taken, inserted] = taken_path_id_.try_emplace(a, path.id);
  if (!inserted && taken->second == path.id) return;
  taken->second = path.id;
  nav->waypoints_m = path.waypoints_m;
  nav->waypoint_yaws_rad.clear();
  if (a != index_) return;
  // Under way: the action starts again from where the robot is, its progress counted on.
  const double done = action_fraction_;
  if (!StartAction(a).ok()) return;  // the same action's controller was made before
  resumed_index_ = a;
  resumed_fraction_ = done;
}

absl::Status RouteExecutor::ResumeAt(const RoutePosition& position, const Pose2& pose_in_map) {
  if (position.action_index == 0 && position.action_fraction == 0.0) return absl::OkStatus();
  RETURN_IF_ERROR(CheckRoutePosition(route_, position));
  const int k = position.action_index;
  std::optional<RouteAction> left =
      RemainderOf(route_.actions[k], position.action_fraction, pose_in_map);
  if (left) {
    route_.actions[k] = *std::move(left);
    resumed_index_ = k;
    resumed_fraction_ = position.action_fraction;
    index_ = k - 1;
    waiting_ = k > 0;  // action k starts once cleared, as after action k - 1
    return absl::OkStatus();
  }
  // Nothing is left of action k: go on with the next, or the route is done.
  index_ = k;
  if (k + 1 >= static_cast<int>(route_.actions.size())) {
    state_ = ExecutionState::kSucceeded;
  } else {
    waiting_ = true;
  }
  return absl::OkStatus();
}

void RouteExecutor::SetHold(const std::optional<SegmentHold>& hold) {
  const bool same = hold && hold_ && hold->action_index == hold_->action_index &&
                    hold->segment == hold_->segment &&
                    hold->gate.translation() == hold_->gate.translation() &&
                    hold->gate.yaw_rad() == hold_->gate.yaw_rad();
  if (!same) stands_at_gate_ = false;
  hold_ = hold;
}

void RouteExecutor::HoldBeforeGate(const ControlInput& input, ExecutorOutput* out) {
  const Eigen::Vector2d velocity_in_map_mps =
      Eigen::Rotation2Dd(input.pose_in_map.yaw_rad()) *
      Eigen::Vector2d(out->command.vx_mps, out->command.vy_mps);
  // Along the robot's own path where it follows one (a path may turn back just before the
  // gate); else by the direction it drives.
  const std::optional<double> along_m = controller_->PathDistanceToGate(hold_->gate);
  constexpr double kArrivedM = 0.05;
  if (along_m && *along_m <= kArrivedM) stands_at_gate_ = true;
  const double limit_mps =
      stands_at_gate_ ? 0.0
      : along_m       ? std::sqrt(2.0 * params_.profile.decel_mps2 * *along_m)
                      : SpeedLimitBeforeGate(hold_->gate, input.pose_in_map.translation(),
                                             velocity_in_map_mps, params_.profile.decel_mps2);
  const double speed_mps = velocity_in_map_mps.norm();
  if (speed_mps <= limit_mps) return;
  // Slowed along its own curve (the turn rate with the speed), to a stop before the gate.
  const double scale = limit_mps / speed_mps;
  out->command.vx_mps *= scale;
  out->command.vy_mps *= scale;
  out->command.yaw_rate_radps *= scale;
  if (limit_mps == 0.0) out->mode = NavigationMode::kIdle;
}

double RouteExecutor::ActionFraction(double controller_fraction) const {
  if (index_ != resumed_index_) return controller_fraction;
  return resumed_fraction_ + (1.0 - resumed_fraction_) * controller_fraction;
}

ExecutorOutput RouteExecutor::Fail(absl::Status status) {
  failure_ = std::move(status);
  state_ = ExecutionState::kFailed;
  controller_.reset();
  ExecutorOutput out;
  out.state = state_;
  out.mode = NavigationMode::kFault;
  out.action_index = index_;
  return out;
}

ExecutorOutput RouteExecutor::Waiting() const {
  ExecutorOutput out;
  out.state = state_;
  out.mode = NavigationMode::kIdle;
  out.action_index = index_;
  out.waiting = true;
  out.action_fraction = 1.0;
  out.progress_fraction =
      static_cast<double>(index_ + 1) / static_cast<double>(route_.actions.size());
  return out;
}

void RouteExecutor::Abort(const absl::Status& reason) {
  if (state_ != ExecutionState::kRunning) return;
  const int index = std::max(index_, 0);
  std::string where = "route";
  if (index < static_cast<int>(route_.actions.size())) {
    where = absl::StrCat("actions[", index, "] (",
                         std::string(ActionTypeName(route_.actions[index].params)), ")");
  }
  (void)Fail(absl::Status(reason.code(), absl::StrCat(where, ": ", reason.message())));
}

ExecutorOutput RouteExecutor::Step(const ControlInput& input,
                                   const std::vector<int>& detected_markers) {
  ExecutorOutput out = StepActions(input, detected_markers);
  out.lift_raised = lift_raised_;
  out.carried_load_m = context_.carried_load_m;
  return out;
}

ExecutorOutput RouteExecutor::StepActions(const ControlInput& input,
                                          const std::vector<int>& detected_markers) {
  ExecutorOutput out;
  out.state = state_;
  if (state_ != ExecutionState::kRunning) {
    out.progress_fraction = state_ == ExecutionState::kSucceeded ? 1.0 : 0.0;
    out.mode = state_ == ExecutionState::kFailed ? NavigationMode::kFault : NavigationMode::kIdle;
    out.action_index = index_;
    return out;
  }
  const double actions = static_cast<double>(route_.actions.size());
  if (index_ < 0) {
    if (route_.actions.empty()) {
      state_ = ExecutionState::kSucceeded;
      out.state = state_;
      out.progress_fraction = 1.0;
      return out;
    }
  }
  if (index_ < 0 || waiting_) {
    if (index_ + 1 > cleared_up_to_) return Waiting();
    waiting_ = false;
    if (absl::Status s = StartAction(index_ + 1); !s.ok()) return Fail(s);
  }
  while (true) {
    const RouteAction& action = route_.actions[index_];
    ControlOutput control = controller_->Step(input);
    if (control.lift_raised) lift_raised_ = *control.lift_raised;
    if (!control.failure.ok()) {
      return Fail(absl::Status(
          control.failure.code(),
          absl::StrCat("actions[", index_, "] (", std::string(ActionTypeName(action.params)),
                       "): ", control.failure.message())));
    }
    bool done = control.done;
    if (action.end.kind == EndConditionKind::kMarkerDetected) {
      const bool seen = std::find(detected_markers.begin(), detected_markers.end(),
                                  action.end.marker_id) != detected_markers.end();
      if (!seen && control.done) {
        return Fail(absl::FailedPreconditionError(absl::StrCat(
            "actions[", index_, "] (", std::string(ActionTypeName(action.params)), "): marker ",
            action.end.marker_id, " was not detected within the action's distance")));
      }
      done = seen;
    }
    out.mode = control.mode;
    out.mode_reason = control.mode_reason;
    out.action_index = index_;
    out.action_fraction = done ? 1.0 : ActionFraction(control.progress_fraction);
    action_fraction_ = out.action_fraction;
    out.progress_fraction = (index_ + out.action_fraction) / actions;
    if (!done) {
      out.command = control.command;
      if (hold_ && hold_->action_index == index_) HoldBeforeGate(input, &out);
      return out;
    }
    const std::optional<Eigen::Vector2d> carried_before_m = context_.carried_load_m;
    context_.carried_load_m = LoadAfter(action, context_, params_);
    // The lift latches and sets down a trolley centred on the robot.
    if (!carried_before_m && context_.carried_load_m) {
      context_.moved_loads.Lifted(input.pose_in_map, *context_.carried_load_m);
    } else if (carried_before_m && !context_.carried_load_m) {
      context_.moved_loads.SetDown(input.pose_in_map, *carried_before_m);
    }
    if (index_ + 1 >= static_cast<int>(route_.actions.size())) {
      state_ = ExecutionState::kSucceeded;
      controller_.reset();
      out.state = state_;
      out.mode = NavigationMode::kIdle;
      out.progress_fraction = 1.0;
      out.command = Twist2{};
      return out;
    }
    if (index_ + 1 > cleared_up_to_) {
      controller_.reset();
      waiting_ = true;
      return Waiting();
    }
    if (absl::Status s = StartAction(index_ + 1); !s.ok()) return Fail(s);
  }
}

}  // namespace fleetnav::agent
