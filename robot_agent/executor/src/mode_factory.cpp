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

bool HasInductiveSensors(const RobotModel& model) {
  for (const SensorMount& mount : model.sensors) {
    if (mount.type == SensorType::kInductive) return true;
  }
  return false;
}

bool HasLaser(const RobotModel& model) {
  for (const SensorMount& mount : model.sensors) {
    if (mount.type == SensorType::kLaser) return true;
  }
  return false;
}

/// The kinds FreeNavigationController has a path tracker for.
bool FreeNavigationSupported(const RobotModel& model) {
  return model.kinematics == Kinematics::kDifferential ||
         model.kinematics == Kinematics::kOmnidirectional ||
         model.kinematics == Kinematics::kAckermann;
}

/// The marker set's pieces of stripe `stripe_id` (of `kind`), or of every stripe of `kind` when
/// stripe_id is 0.
std::vector<StripeMarker> StripePieces(const RouteContext& context, int stripe_id,
                                       MarkerKind kind) {
  std::vector<StripeMarker> pieces;
  if (!context.markers) return pieces;
  for (const StripeMarker& m : context.markers->markers) {
    if (m.kind == kind && (stripe_id == 0 || m.stripe_id == stripe_id)) pieces.push_back(m);
  }
  return pieces;
}

bool HasStripesOfKind(const RouteContext& context, MarkerKind kind) {
  return !StripePieces(context, 0, kind).empty();
}

absl::Status CheckEnd(const RouteAction& action, int index, const RouteContext& context) {
  const EndConditionKind end = action.end.kind;
  const auto refuse = [&](const std::string& why) {
    return absl::FailedPreconditionError(absl::StrCat(Where(action, index), ": ", why));
  };
  switch (end) {
    case EndConditionKind::kDistance:
      return absl::OkStatus();
    case EndConditionKind::kMarkerDetected: {
      if (std::holds_alternative<TurnAction>(action.params) ||
          std::holds_alternative<DockAction>(action.params)) {
        return refuse("cannot end on a marker");
      }
      if (!context.markers.has_value()) {
        return refuse(absl::StrCat("ends on marker ", action.end.marker_id,
                                   " but the robot has no marker set for this map"));
      }
      for (const StripeMarker& m : context.markers->markers) {
        if (m.id == action.end.marker_id && m.kind == MarkerKind::kCalibration) {
          return absl::OkStatus();
        }
      }
      return refuse(absl::StrCat("marker ", action.end.marker_id,
                                 " is not a calibration marker of the marker set"));
    }
    case EndConditionKind::kStripeEnd:
      if (std::holds_alternative<StripeNavigationAction>(action.params)) return absl::OkStatus();
      break;
    case EndConditionKind::kChargerContact:
      if (std::holds_alternative<DockAction>(action.params)) return absl::OkStatus();
      break;
    case EndConditionKind::kGoalReached:
      if (std::holds_alternative<FreeNavigationAction>(action.params)) return absl::OkStatus();
      if (const auto* dock = std::get_if<DockAction>(&action.params);
          dock != nullptr && dock->target == DockTarget::kTrolley) {
        return absl::OkStatus();
      }
      break;
    default:
      break;
  }
  return refuse(absl::StrCat("end condition '", std::string(EndConditionKindName(end)),
                             "' needs sensing this agent version does not have"));
}

absl::Status CheckAction(const RouteAction& action, int index, const RouteContext& context,
                         const ModeParams& params) {
  const auto refuse = [&](const std::string& why) {
    return absl::FailedPreconditionError(absl::StrCat(Where(action, index), ": ", why));
  };
  if (const auto* free = std::get_if<FreeNavigationAction>(&action.params)) {
    if (!FreeNavigationSupported(context.model)) {
      return refuse(absl::StrCat("free navigation for ", context.model.kind_name,
                                 " is not supported by this agent version"));
    }
    if (context.map == nullptr) return refuse("free navigation needs the map (--map)");
    if (absl::Status s = CheckFreeNavigation(*free, context.NavigationModel(), *context.map,
                                             params.free_navigation.padding_m);
        !s.ok()) {
      return refuse(absl::StrCat(s.message(),
                                 context.carried_load_m ? " (with the trolley it carries)" : ""));
    }
  }
  if (std::holds_alternative<UndockAction>(action.params)) {
    if (!context.model.has_lift) {
      return refuse(absl::StrCat(context.model.kind_name, " has no lift to set a trolley down"));
    }
    if (!context.carried_load_m) {
      return refuse("the robot carries no trolley here: undock follows a trolley dock");
    }
  }
  if (std::holds_alternative<MoveAction>(action.params) &&
      context.model.kinematics != Kinematics::kOmnidirectional) {
    return refuse(absl::StrCat(context.model.kind_name,
                               " cannot translate sideways: move is for omnidirectional robots"));
  }
  if (std::holds_alternative<TurnAction>(action.params) &&
      context.model.kinematics == Kinematics::kAckermann) {
    return refuse(
        absl::StrCat(context.model.kind_name, " steers its front wheels and cannot turn in place"));
  }
  if (const auto* fence = std::get_if<FenceNavigationAction>(&action.params)) {
    if (FenceUltrasonic(*fence, context.model) == nullptr) {
      return refuse(absl::StrCat(context.model.kind_name, " has no ",
                                 fence->side == Side::kLeft ? "left" : "right",
                                 " ultrasonic to follow a fence with"));
    }
  }
  if (const auto* stripe = std::get_if<StripeNavigationAction>(&action.params)) {
    if (!HasInductiveSensors(context.model)) {
      return refuse(absl::StrCat(context.model.kind_name, " has no inductive stripe sensors"));
    }
    if (HasStripesOfKind(context, MarkerKind::kFollowStripe) &&
        StripePieces(context, stripe->stripe_id, MarkerKind::kFollowStripe).empty()) {
      return refuse(absl::StrCat("stripe ", stripe->stripe_id, " is not in the marker set"));
    }
  }
  if (const auto* dock = std::get_if<DockAction>(&action.params)) {
    if (dock->target == DockTarget::kTrolley) {
      if (context.model.kinematics != Kinematics::kOmnidirectional || !HasLaser(context.model) ||
          !context.model.has_lift) {
        return refuse(absl::StrCat(context.model.kind_name,
                                   " cannot dock under a trolley: that needs an omnidirectional "
                                   "platform with a laser and a lift"));
      }
      if (context.carried_load_m) {
        return refuse("the robot already carries a trolley: undock it first");
      }
      if (context.markers && !context.markers->trolleys.empty() &&
          context.markers->FindTrolley(dock->target_id) == nullptr) {
        return refuse(absl::StrCat("trolley '", dock->target_id, "' is not on map '",
                                   context.markers->map_id, "'"));
      }
    } else if (!HasInductiveSensors(context.model)) {
      return refuse(absl::StrCat(context.model.kind_name,
                                 " has no inductive sensors to follow a charger stripe with"));
    }
  }
  return CheckEnd(action, index, context);
}

}  // namespace

absl::Status ModeParams::Validate() const {
  if (absl::Status s = profile.Validate(); !s.ok()) return s;
  if (absl::Status s = heading.Validate(); !s.ok()) return s;
  if (absl::Status s = fence.Validate(); !s.ok()) return s;
  if (absl::Status s = stripe.Validate(); !s.ok()) return s;
  if (absl::Status s = docking.Validate(); !s.ok()) return s;
  if (absl::Status s = move.Validate(); !s.ok()) return s;
  if (absl::Status s = trolley_docking.Validate(); !s.ok()) return s;
  return free_navigation.Validate();
}

std::vector<std::string> SupportedActionTypes(const RobotModel& model) {
  std::vector<std::string> types{"straight"};
  if (model.kinematics != Kinematics::kAckermann) types.push_back("turn");
  if (model.FindSensor("ultrasonic_left") != nullptr ||
      model.FindSensor("ultrasonic_right") != nullptr) {
    types.push_back("fence_navigation");
  }
  if (HasInductiveSensors(model)) {
    types.push_back("stripe_navigation");
    types.push_back("dock");
  }
  if (FreeNavigationSupported(model)) types.push_back("free_navigation");
  if (model.kinematics == Kinematics::kOmnidirectional) {
    types.push_back("move");
    if (HasLaser(model) && !HasInductiveSensors(model)) types.push_back("dock");
    if (model.has_lift) types.push_back("undock");
  }
  return types;
}

std::optional<Eigen::Vector2d> LoadAfter(const RouteAction& action, const RouteContext& context,
                                         const ModeParams& params) {
  const TrolleySpec& spec = params.trolley_docking.spec;
  return CarriedLoadAfter(
      action, context.carried_load_m, context.markers ? &*context.markers : nullptr,
      {spec.leg_spacing_x_m + 2 * spec.leg_radius_m, spec.leg_spacing_y_m + 2 * spec.leg_radius_m});
}

absl::Status CheckRoute(const Route& route, const RouteContext& context, const ModeParams& params) {
  // What the robot carries changes along the route.
  RouteContext at = context;
  for (size_t i = 0; i < route.actions.size(); ++i) {
    if (absl::Status s = CheckAction(route.actions[i], static_cast<int>(i), at, params); !s.ok()) {
      return s;
    }
    at.carried_load_m = LoadAfter(route.actions[i], at, params);
  }
  return absl::OkStatus();
}

absl::StatusOr<std::unique_ptr<MotionController>> MakeController(const RouteAction& action,
                                                                 int index,
                                                                 const RouteContext& context,
                                                                 const ModeParams& params,
                                                                 const RouteAction* previous) {
  if (absl::Status s = CheckAction(action, index, context, params); !s.ok()) return s;
  if (const auto* move = std::get_if<MoveAction>(&action.params)) {
    // The direction the platform last travelled in, in its frame (heading held by moves).
    std::optional<Eigen::Vector2d> entry;
    if (previous != nullptr) {
      if (const auto* before = std::get_if<MoveAction>(&previous->params)) {
        entry = Eigen::Vector2d(before->dx_m, before->dy_m);
      } else if (std::holds_alternative<StraightAction>(previous->params)) {
        entry = Eigen::Vector2d(1.0, 0.0);
      }
    }
    // Right after an undock the platform stands under the trolley it set down.
    std::optional<TrolleySpec> leaving;
    if (previous != nullptr && std::holds_alternative<UndockAction>(previous->params)) {
      leaving = params.trolley_docking.spec;
    }
    return std::make_unique<MoveController>(*move, entry, context.model, params.move, leaving);
  }
  if (const auto* straight = std::get_if<StraightAction>(&action.params)) {
    return std::make_unique<StraightController>(straight->distance_m, straight->speed_mps,
                                                params.profile, params.heading);
  }
  if (const auto* turn = std::get_if<TurnAction>(&action.params)) {
    return std::make_unique<TurnController>(turn->angle_rad, turn->yaw_rate_radps, params.profile);
  }
  if (const auto* fence = std::get_if<FenceNavigationAction>(&action.params)) {
    return std::make_unique<FenceFollowingController>(
        *fence, *FenceUltrasonic(*fence, context.model), params.profile, params.fence);
  }
  if (const auto* free = std::get_if<FreeNavigationAction>(&action.params)) {
    return std::make_unique<FreeNavigationController>(
        *free, context.NavigationModel(), context.map, params.free_navigation,
        context.carried_load_m.has_value(), context.moved_loads);
  }
  if (const auto* stripe = std::get_if<StripeNavigationAction>(&action.params)) {
    return std::make_unique<StripeFollowingController>(
        *stripe, action.end.kind, StripePieces(context, 0, MarkerKind::kFollowStripe),
        params.profile, params.stripe);
  }
  if (std::holds_alternative<UndockAction>(action.params)) {
    return std::make_unique<UndockController>(params.trolley_docking.lift_timeout_s);
  }
  if (const DockAction& dock = std::get<DockAction>(action.params);
      dock.target == DockTarget::kTrolley) {
    // The site's placement of the target, when the robot has the marker set: its legs' spacing
    // and where to look for it.
    TrolleyDockingParams docking = params.trolley_docking;
    std::optional<Pose2> expected;
    if (const TrolleyPlacement* placed =
            context.markers ? context.markers->FindTrolley(dock.target_id) : nullptr) {
      docking.spec.leg_spacing_x_m = placed->size_m.x() - 2 * placed->leg_radius_m;
      docking.spec.leg_spacing_y_m = placed->size_m.y() - 2 * placed->leg_radius_m;
      docking.spec.leg_radius_m = placed->leg_radius_m;
      expected = placed->pose;
    }
    return std::make_unique<TrolleyDockingController>(context.model, docking, dock.target_id,
                                                      expected);
  }
  return std::make_unique<ChargerDockingController>(
      StripePieces(context, 0, MarkerKind::kChargerStripe), params.profile, params.stripe,
      params.docking);
}

}  // namespace fleetnav::agent
