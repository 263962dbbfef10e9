#include "fleetnav/core/route.hpp"

#include <cmath>
#include <string>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "strings_internal.hpp"

namespace fleetnav {
namespace {

// Checks one action's parameters and end condition; `where` prefixes every message, e.g.
// "actions[2] (straight)". EndConditionKind::kDistance is the default-constructed end condition
// and therefore also stands for "the action's default" on actions that have no own distance.
class ActionValidator {
 public:
  ActionValidator(std::string where, const EndCondition& end)
      : where_(std::move(where)), end_(end) {}

  absl::Status operator()(const TurnAction& turn) const {
    if (!std::isfinite(turn.angle_rad) || turn.angle_rad == 0.0 ||
        std::abs(turn.angle_rad) > 2.0 * kPi) {
      return Error(absl::StrFormat("angle_rad must be finite, non-zero and within +-2pi, got %g",
                                   turn.angle_rad));
    }
    if (absl::Status status = Positive(turn.yaw_rate_radps, "yaw_rate_radps"); !status.ok()) {
      return status;
    }
    return EndIsOneOf({EndConditionKind::kDistance, EndConditionKind::kMarkerDetected});
  }

  absl::Status operator()(const StraightAction& straight) const {
    if (absl::Status status = Positive(straight.distance_m, "distance_m"); !status.ok()) {
      return status;
    }
    if (absl::Status status = Positive(straight.speed_mps, "speed_mps"); !status.ok()) {
      return status;
    }
    return EndIsOneOf({EndConditionKind::kDistance, EndConditionKind::kMarkerDetected});
  }

  absl::Status operator()(const MoveAction& move) const {
    if (!std::isfinite(move.dx_m) || !std::isfinite(move.dy_m) ||
        std::hypot(move.dx_m, move.dy_m) < 1e-3) {
      return Error(absl::StrFormat("dx_m, dy_m must be finite and move at least 1 mm, got (%g, %g)",
                                   move.dx_m, move.dy_m));
    }
    if (absl::Status status = Positive(move.speed_mps, "speed_mps"); !status.ok()) return status;
    return EndIsOneOf({EndConditionKind::kDistance});
  }

  absl::Status operator()(const FreeNavigationAction& navigation) const {
    for (size_t i = 0; i < navigation.waypoints_m.size(); ++i) {
      if (!navigation.waypoints_m[i].allFinite()) {
        return Error(absl::StrCat("waypoints_m[", i, "] must be finite"));
      }
      if (const std::optional<double> yaw = navigation.WaypointYaw(i);
          yaw && !std::isfinite(*yaw)) {
        return Error(absl::StrCat("waypoints_m[", i, "]: yaw must be finite"));
      }
    }
    if (!navigation.waypoint_yaws_rad.empty() &&
        navigation.waypoint_yaws_rad.size() != navigation.waypoints_m.size()) {
      return Error("waypoint_yaws_rad: one entry per waypoint, or none");
    }
    if (!navigation.goal.IsFinite()) {
      return Error(absl::StrCat("goal must be finite, got ", navigation.goal.DebugString()));
    }
    if (absl::Status status = Positive(navigation.speed_mps, "speed_mps"); !status.ok()) {
      return status;
    }
    return EndIsOneOf({EndConditionKind::kGoalReached, EndConditionKind::kDistance});
  }

  absl::Status operator()(const UndockAction&) const {
    return EndIsOneOf({EndConditionKind::kDistance});
  }

  absl::Status operator()(const FenceNavigationAction& fence) const {
    if (absl::Status status = Positive(fence.fence_distance_m, "fence_distance_m"); !status.ok()) {
      return status;
    }
    if (absl::Status status = DistanceOrSensorEnd(fence.distance_m); !status.ok()) return status;
    if (absl::Status status = Positive(fence.speed_mps, "speed_mps"); !status.ok()) return status;
    return EndIsOneOf({EndConditionKind::kDistance, EndConditionKind::kMarkerDetected,
                       EndConditionKind::kStripeEnd});
  }

  absl::Status operator()(const StripeNavigationAction& stripe) const {
    if (stripe.stripe_id < 0) {
      return Error(absl::StrCat("stripe_id must be >= 0, got ", stripe.stripe_id));
    }
    if (absl::Status status = DistanceOrSensorEnd(stripe.distance_m); !status.ok()) {
      return status;
    }
    if (absl::Status status = Positive(stripe.speed_mps, "speed_mps"); !status.ok()) {
      return status;
    }
    return EndIsOneOf({EndConditionKind::kDistance, EndConditionKind::kMarkerDetected,
                       EndConditionKind::kStripeEnd});
  }

  absl::Status operator()(const DockAction& dock) const {
    if (dock.target == DockTarget::kCharger) {
      return EndIsOneOf({EndConditionKind::kChargerContact, EndConditionKind::kDistance});
    }
    if (dock.target_id.empty()) return Error("a trolley dock needs target_id: which trolley");
    return EndIsOneOf({EndConditionKind::kGoalReached, EndConditionKind::kDistance});
  }

 private:
  absl::Status Error(absl::string_view message) const {
    return absl::InvalidArgumentError(absl::StrCat(where_, ": ", message));
  }

  absl::Status Positive(double value, std::string_view field) const {
    if (std::isfinite(value) && value > 0.0) return absl::OkStatus();
    return Error(absl::StrFormat("%s must be > 0, got %g", field, value));
  }

  // A followed fence or stripe may run for distance_m = 0 ("until the sensor says so") only
  // when a marker or the stripe's end stops it; otherwise distance_m must be positive.
  absl::Status DistanceOrSensorEnd(double distance_m) const {
    if (!std::isfinite(distance_m) || distance_m < 0.0) {
      return Error(absl::StrFormat("distance_m must be finite and >= 0, got %g", distance_m));
    }
    const bool sensor_end =
        end_.kind == EndConditionKind::kMarkerDetected || end_.kind == EndConditionKind::kStripeEnd;
    if (distance_m == 0.0 && !sensor_end) {
      return Error("distance_m must be > 0 unless the action ends on a marker or stripe_end");
    }
    return absl::OkStatus();
  }

  absl::Status EndIsOneOf(std::initializer_list<EndConditionKind> allowed) const {
    for (EndConditionKind kind : allowed) {
      if (end_.kind == kind) return absl::OkStatus();
    }
    std::string names;
    for (EndConditionKind kind : allowed) {
      absl::StrAppend(&names, names.empty() ? "" : ", ",
                      internal::ToAbsl(EndConditionKindName(kind)));
    }
    return Error(absl::StrCat("end condition '", internal::ToAbsl(EndConditionKindName(end_.kind)),
                              "' does not fit this action (allowed: ", names, ")"));
  }

  std::string where_;
  const EndCondition& end_;
};

}  // namespace

absl::Status CheckRoutePosition(const Route& route, const RoutePosition& position) {
  const int actions = static_cast<int>(route.actions.size());
  if (position.action_index < 0 ||
      (position.action_index >= actions && position.action_index != 0)) {
    return absl::InvalidArgumentError(absl::StrCat("resume position: action ",
                                                   position.action_index, " is not in route '",
                                                   route.name, "' of ", actions, " actions"));
  }
  if (!(position.action_fraction >= 0.0 && position.action_fraction <= 1.0)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "resume position: fraction must be in [0, 1], got ", position.action_fraction));
  }
  return absl::OkStatus();
}

absl::Status Route::Validate() const {
  if (name.empty()) return absl::InvalidArgumentError("route name must not be empty");
  if (actions.empty()) {
    return absl::InvalidArgumentError(
        absl::StrCat("route '", name, "': actions must not be empty"));
  }
  for (size_t i = 0; i < actions.size(); ++i) {
    const RouteAction& action = actions[i];
    const ActionValidator validator(
        absl::StrCat("actions[", i, "] (", internal::ToAbsl(ActionTypeName(action.params)), ")"),
        action.end);
    if (absl::Status status = std::visit(validator, action.params); !status.ok()) return status;
  }
  return absl::OkStatus();
}

std::string_view ActionTypeName(const ActionParams& params) {
  struct Namer {
    std::string_view operator()(const TurnAction&) const { return "turn"; }
    std::string_view operator()(const StraightAction&) const { return "straight"; }
    std::string_view operator()(const MoveAction&) const { return "move"; }
    std::string_view operator()(const FreeNavigationAction&) const { return "free_navigation"; }
    std::string_view operator()(const FenceNavigationAction&) const { return "fence_navigation"; }
    std::string_view operator()(const StripeNavigationAction&) const { return "stripe_navigation"; }
    std::string_view operator()(const DockAction&) const { return "dock"; }
    std::string_view operator()(const UndockAction&) const { return "undock"; }
  };
  return std::visit(Namer{}, params);
}

std::string_view EndConditionKindName(EndConditionKind kind) {
  switch (kind) {
    case EndConditionKind::kDistance:
      return "distance";
    case EndConditionKind::kMarkerDetected:
      return "marker_detected";
    case EndConditionKind::kStripeEnd:
      return "stripe_end";
    case EndConditionKind::kChargerContact:
      return "charger_contact";
    case EndConditionKind::kGoalReached:
      return "goal_reached";
  }
  return "distance";
}

absl::StatusOr<EndConditionKind> ParseEndConditionKind(std::string_view name) {
  for (EndConditionKind kind : {EndConditionKind::kDistance, EndConditionKind::kMarkerDetected,
                                EndConditionKind::kStripeEnd, EndConditionKind::kChargerContact,
                                EndConditionKind::kGoalReached}) {
    if (name == EndConditionKindName(kind)) return kind;
  }
  return absl::InvalidArgumentError(absl::StrCat(
      "unknown end condition '", internal::ToAbsl(name),
      "' (expected distance, marker_detected, stripe_end, charger_contact or goal_reached)"));
}

std::optional<Eigen::Vector2d> CarriedLoadAfter(const RouteAction& action,
                                                const std::optional<Eigen::Vector2d>& before_m,
                                                const MarkerSet* markers,
                                                const Eigen::Vector2d& unknown_trolley_size_m) {
  if (std::holds_alternative<UndockAction>(action.params)) return std::nullopt;
  const auto* dock = std::get_if<DockAction>(&action.params);
  if (dock == nullptr || dock->target != DockTarget::kTrolley) return before_m;
  const TrolleyPlacement* placed = markers ? markers->FindTrolley(dock->target_id) : nullptr;
  return placed ? placed->size_m : unknown_trolley_size_m;
}

}  // namespace fleetnav
