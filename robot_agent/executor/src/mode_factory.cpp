#include "fleetnav/robot_agent/mode_factory.hpp"

#include <string>

#include "absl/strings/str_cat.h"

namespace fleetnav::agent {
namespace {

std::string Where(const RouteAction& action, int index) {
  return absl::StrCat("actions[", index, "] (", std::string(ActionTypeName(action.params)), ")");
}

const SensorMount* FenceUltrasonic(const FenceNavigationAction& fence, const RobotModel& model) {
  const SensorMount* mount =
      model.FindSensor(fence.side == Side::kLeft ? "ultrasonic_left" : "ultrasonic_right");
  return mount != nullptr && mount->type == SensorType::kUltrasonic ? mount : nullptr;
}

absl::Status CheckAction(const RouteAction& action, int index, const RouteContext& context) {
  const bool supported = std::holds_alternative<TurnAction>(action.params) ||
                         std::holds_alternative<StraightAction>(action.params) ||
                         std::holds_alternative<FenceNavigationAction>(action.params);
  if (!supported) {
    return absl::FailedPreconditionError(
        absl::StrCat(Where(action, index), ": not supported by this agent version"));
  }
  if (const auto* fence = std::get_if<FenceNavigationAction>(&action.params)) {
    if (FenceUltrasonic(*fence, context.model) == nullptr) {
      return absl::FailedPreconditionError(absl::StrCat(
          Where(action, index), ": ", context.model.kind_name, " has no ",
          fence->side == Side::kLeft ? "left" : "right", " ultrasonic to follow a fence with"));
    }
  }
  switch (action.end.kind) {
    case EndConditionKind::kDistance:
      return absl::OkStatus();
    case EndConditionKind::kMarkerDetected: {
      if (std::holds_alternative<TurnAction>(action.params)) {
        return absl::FailedPreconditionError(
            absl::StrCat(Where(action, index), ": a turn cannot end on a marker"));
      }
      if (!context.markers.has_value()) {
        return absl::FailedPreconditionError(
            absl::StrCat(Where(action, index), ": ends on marker ", action.end.marker_id,
                         " but the robot has no marker set for this map"));
      }
      for (const StripeMarker& m : context.markers->markers) {
        if (m.id == action.end.marker_id && m.kind == MarkerKind::kCalibration) {
          return absl::OkStatus();
        }
      }
      return absl::FailedPreconditionError(
          absl::StrCat(Where(action, index), ": marker ", action.end.marker_id,
                       " is not a calibration marker of the marker set"));
    }
    default:
      return absl::FailedPreconditionError(absl::StrCat(
          Where(action, index), ": end condition '",
          std::string(EndConditionKindName(action.end.kind)),
          "' needs sensing this agent version does not have"));
  }
}

}  // namespace

absl::Status ModeParams::Validate() const {
  if (absl::Status s = profile.Validate(); !s.ok()) return s;
  if (absl::Status s = heading.Validate(); !s.ok()) return s;
  return fence.Validate();
}

std::vector<std::string> SupportedActionTypes() {
  return {"straight", "turn", "fence_navigation"};
}

absl::Status CheckRoute(const Route& route, const RouteContext& context) {
  for (size_t i = 0; i < route.actions.size(); ++i) {
    if (absl::Status s = CheckAction(route.actions[i], static_cast<int>(i), context); !s.ok()) {
      return s;
    }
  }
  return absl::OkStatus();
}

absl::StatusOr<std::unique_ptr<MotionController>> MakeController(const RouteAction& action,
                                                                 int index,
                                                                 const RouteContext& context,
                                                                 const ModeParams& params) {
  if (absl::Status s = CheckAction(action, index, context); !s.ok()) return s;
  if (const auto* straight = std::get_if<StraightAction>(&action.params)) {
    return std::make_unique<StraightController>(straight->distance_m, straight->speed_mps,
                                                params.profile, params.heading);
  }
  if (const auto* turn = std::get_if<TurnAction>(&action.params)) {
    return std::make_unique<TurnController>(turn->angle_rad, turn->yaw_rate_radps,
                                            params.profile);
  }
  const auto& fence = std::get<FenceNavigationAction>(action.params);
  return std::make_unique<FenceFollowingController>(
      fence, *FenceUltrasonic(fence, context.model), params.profile, params.fence);
}

}  // namespace fleetnav::agent
