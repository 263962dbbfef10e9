#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"

namespace fleetnav {

/// What ends an action (Lely thesis §6.3: "until distance or stripe").
enum class EndConditionKind {
  kDistance,        ///< the action's own distance or angle is covered
  kMarkerDetected,  ///< an inductive sensor crosses the stripe marker `marker_id`
  kStripeEnd,       ///< the followed stripe ends
  kChargerContact,  ///< the charger contact closes
  kGoalReached,     ///< the navigation goal is reached within tolerance
};

struct EndCondition {
  EndConditionKind kind = EndConditionKind::kDistance;
  int marker_id = 0;  ///< for kMarkerDetected
};

/// Turn in place by angle_rad (positive = counter-clockwise / left).
struct TurnAction {
  double angle_rad = 0.0;
  double yaw_rate_radps = 0.3;
};
/// Drive straight, holding the initial heading (PID), for distance_m (> 0 forward).
struct StraightAction {
  double distance_m = 0.0;
  double speed_mps = 0.25;
};
/// Map-based navigation through waypoints to a goal pose. A waypoint may fix the robot's yaw
/// there (`waypoint_yaws_rad`: empty, or one entry per waypoint, nullopt where free); without it
/// the robot faces the next point.
struct FreeNavigationAction {
  std::vector<Eigen::Vector2d> waypoints_m;
  Pose2 goal;
  double speed_mps = 0.25;
  std::vector<std::optional<double>> waypoint_yaws_rad;
  std::optional<double> WaypointYaw(size_t i) const {
    return i < waypoint_yaws_rad.size() ? waypoint_yaws_rad[i] : std::nullopt;
  }
};
enum class Side { kLeft, kRight };
/// Follow a feeding fence on one side at a set distance (ultrasonic PID), for distance_m.
struct FenceNavigationAction {
  Side side = Side::kLeft;
  double fence_distance_m = 0.5;
  double distance_m = 0.0;
  double speed_mps = 0.25;
};
/// Follow a numbered floor stripe with the inductive pair, for distance_m.
struct StripeNavigationAction {
  int stripe_id = 0;
  double distance_m = 0.0;
  double speed_mps = 0.25;
};
/// Translate by (dx_m, dy_m) in the robot's frame at the action's start, holding that heading:
/// an omnidirectional platform's sideways moves and reversals (KUKA thesis ch. 9). Only robots
/// that can translate sideways run it.
struct MoveAction {
  double dx_m = 0.0;
  double dy_m = 0.0;
  double speed_mps = 0.25;
};
enum class DockTarget { kCharger, kTrolley };
/// Dock at the charger or under a trolley. Docking under a trolley ends with the platform's
/// lift raised under it: the trolley is latched and carried until an UndockAction.
struct DockAction {
  DockTarget target = DockTarget::kCharger;
  std::string target_id;
};
/// Lower the lift and leave the carried trolley standing where it is. The robot stays under it;
/// a following move drives out. Only after a trolley dock.
struct UndockAction {};

using ActionParams =
    std::variant<TurnAction, StraightAction, FreeNavigationAction, FenceNavigationAction,
                 StripeNavigationAction, DockAction, MoveAction, UndockAction>;

/// One step of a route with its end condition.
struct RouteAction {
  ActionParams params;
  EndCondition end;
};

/// Where a robot stands in a route: inside action `action_index`, of which `action_fraction`
/// (0..1) is done. {0, 0} is the route's beginning.
struct RoutePosition {
  int action_index = 0;
  double action_fraction = 0.0;
};

/// A named, ordered list of actions on one map (the thesis's route file, §6.3). Validate()
/// checks each action on its own (finite numbers, non-zero distance or angle, positive speed,
/// end condition fitting the action); errors are InvalidArgument and name the action's index,
/// e.g. "actions[2] (straight): distance_m must be > 0".
struct Route {
  std::string name;
  std::string map_id;
  std::vector<RouteAction> actions;

  absl::Status Validate() const;
};

/// InvalidArgument unless `position` lies in `route`: an action index of it (0 for an empty
/// route) and a fraction in [0, 1].
absl::Status CheckRoutePosition(const Route& route, const RoutePosition& position);

struct MarkerSet;

/// The outline (length × width, metres) of what a robot carries on its lift once `action` is
/// done, given what it carried before (nullopt: nothing): a trolley dock latches the trolley,
/// its size from `markers` (or `unknown_trolley_size_m` when the marker set is absent or does
/// not hold it); an undock sets the load down; every other action keeps it.
std::optional<Eigen::Vector2d> CarriedLoadAfter(const RouteAction& action,
                                                const std::optional<Eigen::Vector2d>& before_m,
                                                const MarkerSet* markers,
                                                const Eigen::Vector2d& unknown_trolley_size_m);

std::string_view ActionTypeName(const ActionParams& params);
std::string_view EndConditionKindName(EndConditionKind kind);
absl::StatusOr<EndConditionKind> ParseEndConditionKind(std::string_view name);

/// Route YAML:
///   name: feed-round-1
///   map: barn
///   actions:
///     - straight: {distance: 5.0, speed: 0.25}
///     - turn: {angle_deg: 90, yaw_rate: 0.3}
///     - straight: {distance: 3.0}
///       until: {marker: 4}            # optional end condition
///     - free_navigation: {waypoints: [[1, 2], [3, 4, 90]], goal: {x: 5, y: 6, yaw_deg: 90}}
///                                  # a waypoint [x, y, yaw_deg] fixes the yaw there
///     - fence_navigation: {side: left, fence_distance: 0.5, distance: 10}
///     - stripe_navigation: {stripe: 3, distance: 12}
///       until: stripe_end
///     - dock: {target: charger}
///     - move: {dx: 0, dy: 1.0, speed: 0.2}  # sideways, heading held (omnidirectional robots)
///     - dock: {target: trolley, target_id: trolley-2}  # under it, lift raised: carried
///     - undock: {}                       # lift lowered: the trolley stands
/// Unknown action types and unknown keys are InvalidArgument naming the index.
absl::StatusOr<Route> ParseRouteYaml(std::string_view yaml_text);
std::string RouteToYaml(const Route& route);
absl::StatusOr<Route> LoadRoute(const std::string& path);
absl::Status SaveRoute(const Route& route, const std::string& path);

}  // namespace fleetnav
