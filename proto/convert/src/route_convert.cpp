#include "fleetnav/proto/route_convert.hpp"

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/geometry_convert.hpp"

namespace fleetnav {
namespace {

// Enum values line up one to one after the UNSPECIFIED slot.
v1::EndConditionKind EndKindToProto(EndConditionKind kind) {
  return static_cast<v1::EndConditionKind>(static_cast<int>(kind) + 1);
}

// The end condition an action has when the wire leaves it unspecified.
EndConditionKind DefaultEndKind(const ActionParams& params) {
  if (std::holds_alternative<FreeNavigationAction>(params)) return EndConditionKind::kGoalReached;
  if (const auto* dock = std::get_if<DockAction>(&params)) {
    return dock->target == DockTarget::kCharger ? EndConditionKind::kChargerContact
                                                : EndConditionKind::kGoalReached;
  }
  return EndConditionKind::kDistance;
}

absl::StatusOr<EndConditionKind> EndKindFromProto(int value, const ActionParams& params,
                                                  const std::string& field) {
  if (value == v1::END_CONDITION_KIND_UNSPECIFIED) return DefaultEndKind(params);
  if (value < 0 || value > v1::END_CONDITION_KIND_GOAL_REACHED) {
    return absl::InvalidArgumentError(absl::StrCat(field, ".end.kind: unknown value ", value));
  }
  return static_cast<EndConditionKind>(value - 1);
}

absl::StatusOr<Side> SideFromProto(int value, const std::string& field) {
  if (value == v1::SIDE_LEFT) return Side::kLeft;
  if (value == v1::SIDE_RIGHT) return Side::kRight;
  return absl::InvalidArgumentError(
      absl::StrCat(field, ".fence_navigation.side: unspecified or unknown value ", value));
}

absl::StatusOr<DockTarget> DockTargetFromProto(int value, const std::string& field) {
  if (value == v1::DOCK_TARGET_CHARGER) return DockTarget::kCharger;
  if (value == v1::DOCK_TARGET_TROLLEY) return DockTarget::kTrolley;
  return absl::InvalidArgumentError(
      absl::StrCat(field, ".dock.target: unspecified or unknown value ", value));
}

struct ParamsToProto {
  v1::RouteAction* out;
  void operator()(const TurnAction& a) const {
    out->mutable_turn()->set_angle_rad(a.angle_rad);
    out->mutable_turn()->set_yaw_rate_radps(a.yaw_rate_radps);
  }
  void operator()(const StraightAction& a) const {
    out->mutable_straight()->set_distance_m(a.distance_m);
    out->mutable_straight()->set_speed_mps(a.speed_mps);
  }
  void operator()(const MoveAction& a) const {
    out->mutable_move()->set_dx_m(a.dx_m);
    out->mutable_move()->set_dy_m(a.dy_m);
    out->mutable_move()->set_speed_mps(a.speed_mps);
  }
  void operator()(const FreeNavigationAction& a) const {
    v1::FreeNavigationAction* wire = out->mutable_free_navigation();
    for (const Eigen::Vector2d& waypoint : a.waypoints_m)
      *wire->add_waypoints() = ToProto(waypoint);
    *wire->mutable_goal() = ToProto(a.goal);
    wire->set_speed_mps(a.speed_mps);
    for (size_t i = 0; i < a.waypoint_yaws_rad.size(); ++i) {
      if (!a.waypoint_yaws_rad[i]) continue;
      v1::WaypointYaw* yaw = wire->add_waypoint_yaws();
      yaw->set_index(static_cast<uint32_t>(i));
      yaw->set_yaw_rad(*a.waypoint_yaws_rad[i]);
    }
  }
  void operator()(const FenceNavigationAction& a) const {
    v1::FenceNavigationAction* wire = out->mutable_fence_navigation();
    wire->set_side(a.side == Side::kLeft ? v1::SIDE_LEFT : v1::SIDE_RIGHT);
    wire->set_fence_distance_m(a.fence_distance_m);
    wire->set_distance_m(a.distance_m);
    wire->set_speed_mps(a.speed_mps);
  }
  void operator()(const StripeNavigationAction& a) const {
    v1::StripeNavigationAction* wire = out->mutable_stripe_navigation();
    wire->set_stripe_id(a.stripe_id);
    wire->set_distance_m(a.distance_m);
    wire->set_speed_mps(a.speed_mps);
  }
  void operator()(const DockAction& a) const {
    v1::DockAction* wire = out->mutable_dock();
    wire->set_target(a.target == DockTarget::kCharger ? v1::DOCK_TARGET_CHARGER
                                                      : v1::DOCK_TARGET_TROLLEY);
    wire->set_target_id(a.target_id);
  }
  void operator()(const UndockAction&) const { out->mutable_undock(); }
};

absl::StatusOr<ActionParams> ParamsFromProto(const v1::RouteAction& wire,
                                             const std::string& field) {
  switch (wire.action_case()) {
    case v1::RouteAction::kTurn:
      return TurnAction{wire.turn().angle_rad(), wire.turn().yaw_rate_radps()};
    case v1::RouteAction::kStraight:
      return StraightAction{wire.straight().distance_m(), wire.straight().speed_mps()};
    case v1::RouteAction::kMove:
      return MoveAction{wire.move().dx_m(), wire.move().dy_m(), wire.move().speed_mps()};
    case v1::RouteAction::kUndock:
      return UndockAction{};
    case v1::RouteAction::kFreeNavigation: {
      FreeNavigationAction action;
      const v1::FreeNavigationAction& nav = wire.free_navigation();
      for (int i = 0; i < nav.waypoints_size(); ++i) {
        ASSIGN_OR_RETURN(Eigen::Vector2d waypoint,
                         FromProto(nav.waypoints(i), absl::StrCat(field, ".waypoints[", i, "]")));
        action.waypoints_m.push_back(waypoint);
      }
      ASSIGN_OR_RETURN(action.goal, FromProto(nav.goal(), absl::StrCat(field, ".goal")));
      action.speed_mps = nav.speed_mps();
      if (nav.waypoint_yaws_size() > 0) {
        action.waypoint_yaws_rad.assign(action.waypoints_m.size(), std::nullopt);
      }
      for (const v1::WaypointYaw& yaw : nav.waypoint_yaws()) {
        if (yaw.index() >= action.waypoints_m.size()) {
          return absl::InvalidArgumentError(
              absl::StrCat(field, ".waypoint_yaws: index ", yaw.index(), " is not a waypoint's"));
        }
        action.waypoint_yaws_rad[yaw.index()] = yaw.yaw_rad();
      }
      return action;
    }
    case v1::RouteAction::kFenceNavigation: {
      const v1::FenceNavigationAction& fence = wire.fence_navigation();
      FenceNavigationAction action;
      ASSIGN_OR_RETURN(action.side, SideFromProto(fence.side(), field));
      action.fence_distance_m = fence.fence_distance_m();
      action.distance_m = fence.distance_m();
      action.speed_mps = fence.speed_mps();
      return action;
    }
    case v1::RouteAction::kStripeNavigation:
      return StripeNavigationAction{wire.stripe_navigation().stripe_id(),
                                    wire.stripe_navigation().distance_m(),
                                    wire.stripe_navigation().speed_mps()};
    case v1::RouteAction::kDock: {
      DockAction action;
      ASSIGN_OR_RETURN(action.target, DockTargetFromProto(wire.dock().target(), field));
      action.target_id = wire.dock().target_id();
      return action;
    }
    case v1::RouteAction::ACTION_NOT_SET:
      break;
  }
  return absl::InvalidArgumentError(absl::StrCat(field, ": no action type set"));
}

}  // namespace

v1::Route ToProto(const Route& route) {
  v1::Route out;
  out.set_name(route.name);
  out.set_map_id(route.map_id);
  for (const RouteAction& action : route.actions) {
    v1::RouteAction* wire = out.add_actions();
    std::visit(ParamsToProto{wire}, action.params);
    wire->mutable_end()->set_kind(EndKindToProto(action.end.kind));
    wire->mutable_end()->set_marker_id(action.end.marker_id);
  }
  return out;
}

absl::StatusOr<Route> FromProto(const v1::Route& route) {
  Route out;
  out.name = route.name();
  out.map_id = route.map_id();
  for (int i = 0; i < route.actions_size(); ++i) {
    const std::string field = absl::StrCat("actions[", i, "]");
    const v1::RouteAction& wire = route.actions(i);
    RouteAction action;
    ASSIGN_OR_RETURN(action.params, ParamsFromProto(wire, field));
    ASSIGN_OR_RETURN(action.end.kind, EndKindFromProto(wire.end().kind(), action.params, field));
    action.end.marker_id = wire.end().marker_id();
    out.actions.push_back(std::move(action));
  }
  RETURN_IF_ERROR(out.Validate());
  return out;
}

}  // namespace fleetnav
