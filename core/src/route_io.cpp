// Route YAML (Lely thesis §6.3: a route is an ordered list of actions, each run until its
// distance is covered or a sensor event ends it). The format is documented in route.hpp.
#include <yaml-cpp/yaml.h>

#include <array>
#include <cstdlib>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "io_internal.hpp"

namespace fleetnav {
namespace {

using internal::AsDouble;
using internal::FormatDouble;

constexpr std::array<absl::string_view, 8> kActionTypes = {
    "turn", "straight", "free_navigation", "fence_navigation", "stripe_navigation",
    "dock", "move",     "undock"};
constexpr char kUntilKey[] = "until";

bool IsActionType(absl::string_view key) {
  for (absl::string_view type : kActionTypes) {
    if (key == type) return true;
  }
  return false;
}

bool Has(const YAML::Node& node, const char* key) {
  const YAML::Node child = node[key];
  return child.IsDefined() && !child.IsNull();
}

absl::StatusOr<double> RequiredDouble(const YAML::Node& node, const char* key,
                                      const std::string& where) {
  if (!Has(node, key))
    return absl::InvalidArgumentError(absl::StrCat(where, ": missing '", key, "'"));
  return AsDouble(node[key], absl::StrCat(where, ": ", key));
}

absl::Status OptionalDouble(const YAML::Node& node, const char* key, const std::string& where,
                            double& value) {
  if (!Has(node, key)) return absl::OkStatus();
  ASSIGN_OR_RETURN(value, AsDouble(node[key], absl::StrCat(where, ": ", key)));
  return absl::OkStatus();
}

// An angle given either in degrees (`<stem>_deg`) or radians (`<stem>_rad`).
absl::StatusOr<double> AngleRad(const YAML::Node& node, const std::string& stem, bool required,
                                const std::string& where) {
  const std::string deg_key = stem + "_deg";
  const std::string rad_key = stem + "_rad";
  const bool has_deg = Has(node, deg_key.c_str());
  const bool has_rad = Has(node, rad_key.c_str());
  if (has_deg && has_rad) {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": give either '", deg_key, "' or '", rad_key, "', not both"));
  }
  if (has_deg) {
    ASSIGN_OR_RETURN(const double deg, AsDouble(node[deg_key], absl::StrCat(where, ": ", deg_key)));
    return DegToRad(deg);
  }
  if (has_rad) return AsDouble(node[rad_key], absl::StrCat(where, ": ", rad_key));
  if (required) {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": missing '", deg_key, "' (or '", rad_key, "')"));
  }
  return 0.0;
}

absl::StatusOr<TurnAction> ParseTurn(const YAML::Node& node, const std::string& where) {
  RETURN_IF_ERROR(internal::CheckKnownKeys(node, {"angle_deg", "angle_rad", "yaw_rate"}, where));
  TurnAction turn;
  ASSIGN_OR_RETURN(turn.angle_rad, AngleRad(node, "angle", /*required=*/true, where));
  RETURN_IF_ERROR(OptionalDouble(node, "yaw_rate", where, turn.yaw_rate_radps));
  return turn;
}

absl::StatusOr<StraightAction> ParseStraight(const YAML::Node& node, const std::string& where) {
  RETURN_IF_ERROR(internal::CheckKnownKeys(node, {"distance", "speed"}, where));
  StraightAction straight;
  ASSIGN_OR_RETURN(straight.distance_m, RequiredDouble(node, "distance", where));
  RETURN_IF_ERROR(OptionalDouble(node, "speed", where, straight.speed_mps));
  return straight;
}

absl::StatusOr<MoveAction> ParseMove(const YAML::Node& node, const std::string& where) {
  RETURN_IF_ERROR(internal::CheckKnownKeys(node, {"dx", "dy", "speed"}, where));
  MoveAction move;
  RETURN_IF_ERROR(OptionalDouble(node, "dx", where, move.dx_m));
  RETURN_IF_ERROR(OptionalDouble(node, "dy", where, move.dy_m));
  RETURN_IF_ERROR(OptionalDouble(node, "speed", where, move.speed_mps));
  return move;
}

/// Waypoints [x, y] or [x, y, yaw_deg] into `navigation`.
absl::Status ParseWaypoints(const YAML::Node& node, const std::string& where,
                            FreeNavigationAction* navigation) {
  if (!node.IsSequence()) {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": waypoints: expected a list of [x, y] or [x, y, yaw_deg]"));
  }
  bool any_yaw = false;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string field = absl::StrCat(where, ": waypoints[", i, "]");
    const YAML::Node point = node[i];
    if (!point.IsSequence() || (point.size() != 2 && point.size() != 3)) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ": expected [x, y] or [x, y, yaw_deg]"));
    }
    ASSIGN_OR_RETURN(const double x_m, AsDouble(point[0], field));
    ASSIGN_OR_RETURN(const double y_m, AsDouble(point[1], field));
    navigation->waypoints_m.emplace_back(x_m, y_m);
    std::optional<double> yaw;
    if (point.size() == 3) {
      ASSIGN_OR_RETURN(const double yaw_deg, AsDouble(point[2], field));
      yaw = DegToRad(yaw_deg);
      any_yaw = true;
    }
    navigation->waypoint_yaws_rad.push_back(yaw);
  }
  if (!any_yaw) navigation->waypoint_yaws_rad.clear();
  return absl::OkStatus();
}

absl::StatusOr<Pose2> ParseGoal(const YAML::Node& node, const std::string& where) {
  const std::string field = absl::StrCat(where, ": goal");
  if (!node.IsMap()) return absl::InvalidArgumentError(absl::StrCat(field, ": expected a mapping"));
  RETURN_IF_ERROR(internal::CheckKnownKeys(node, {"x", "y", "yaw_deg", "yaw_rad"}, field));
  ASSIGN_OR_RETURN(const double x_m, RequiredDouble(node, "x", field));
  ASSIGN_OR_RETURN(const double y_m, RequiredDouble(node, "y", field));
  ASSIGN_OR_RETURN(const double yaw_rad, AngleRad(node, "yaw", /*required=*/false, field));
  return Pose2(x_m, y_m, yaw_rad);
}

absl::StatusOr<FreeNavigationAction> ParseFreeNavigation(const YAML::Node& node,
                                                         const std::string& where) {
  RETURN_IF_ERROR(internal::CheckKnownKeys(node, {"waypoints", "goal", "speed"}, where));
  FreeNavigationAction navigation;
  if (Has(node, "waypoints")) {
    RETURN_IF_ERROR(ParseWaypoints(node["waypoints"], where, &navigation));
  }
  if (!Has(node, "goal"))
    return absl::InvalidArgumentError(absl::StrCat(where, ": missing 'goal'"));
  ASSIGN_OR_RETURN(navigation.goal, ParseGoal(node["goal"], where));
  RETURN_IF_ERROR(OptionalDouble(node, "speed", where, navigation.speed_mps));
  return navigation;
}

absl::StatusOr<Side> ParseSide(const YAML::Node& node, const std::string& where) {
  ASSIGN_OR_RETURN(const std::string side, internal::AsString(node, absl::StrCat(where, ": side")));
  if (side == "left") return Side::kLeft;
  if (side == "right") return Side::kRight;
  return absl::InvalidArgumentError(
      absl::StrCat(where, ": side must be left or right, got '", side, "'"));
}

absl::StatusOr<FenceNavigationAction> ParseFenceNavigation(const YAML::Node& node,
                                                           const std::string& where) {
  RETURN_IF_ERROR(
      internal::CheckKnownKeys(node, {"side", "fence_distance", "distance", "speed"}, where));
  FenceNavigationAction fence;
  if (!Has(node, "side"))
    return absl::InvalidArgumentError(absl::StrCat(where, ": missing 'side'"));
  ASSIGN_OR_RETURN(fence.side, ParseSide(node["side"], where));
  RETURN_IF_ERROR(OptionalDouble(node, "fence_distance", where, fence.fence_distance_m));
  RETURN_IF_ERROR(OptionalDouble(node, "distance", where, fence.distance_m));
  RETURN_IF_ERROR(OptionalDouble(node, "speed", where, fence.speed_mps));
  return fence;
}

absl::StatusOr<StripeNavigationAction> ParseStripeNavigation(const YAML::Node& node,
                                                             const std::string& where) {
  RETURN_IF_ERROR(internal::CheckKnownKeys(node, {"stripe", "distance", "speed"}, where));
  StripeNavigationAction stripe;
  if (!Has(node, "stripe")) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": missing 'stripe'"));
  }
  ASSIGN_OR_RETURN(stripe.stripe_id,
                   internal::AsInt(node["stripe"], absl::StrCat(where, ": stripe")));
  RETURN_IF_ERROR(OptionalDouble(node, "distance", where, stripe.distance_m));
  RETURN_IF_ERROR(OptionalDouble(node, "speed", where, stripe.speed_mps));
  return stripe;
}

absl::StatusOr<DockAction> ParseDock(const YAML::Node& node, const std::string& where) {
  RETURN_IF_ERROR(internal::CheckKnownKeys(node, {"target", "target_id"}, where));
  DockAction dock;
  if (!Has(node, "target")) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": missing 'target'"));
  }
  ASSIGN_OR_RETURN(const std::string target,
                   internal::AsString(node["target"], absl::StrCat(where, ": target")));
  if (target == "charger") {
    dock.target = DockTarget::kCharger;
  } else if (target == "trolley") {
    dock.target = DockTarget::kTrolley;
  } else {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": target must be charger or trolley, got '", target, "'"));
  }
  if (Has(node, "target_id")) {
    ASSIGN_OR_RETURN(dock.target_id,
                     internal::AsString(node["target_id"], absl::StrCat(where, ": target_id")));
  }
  return dock;
}

absl::StatusOr<ActionParams> ParseParams(std::string_view type, const YAML::Node& node,
                                         const std::string& where) {
  if (type == "undock" && node.IsNull()) return UndockAction{};  // `- undock:` takes no parameters
  if (!node.IsMap()) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": expected a mapping of parameters"));
  }
  if (type == "turn") return ParseTurn(node, where);
  if (type == "straight") return ParseStraight(node, where);
  if (type == "free_navigation") return ParseFreeNavigation(node, where);
  if (type == "fence_navigation") return ParseFenceNavigation(node, where);
  if (type == "stripe_navigation") return ParseStripeNavigation(node, where);
  if (type == "move") return ParseMove(node, where);
  if (type == "undock") {
    RETURN_IF_ERROR(internal::CheckKnownKeys(node, {}, where));
    return UndockAction{};
  }
  return ParseDock(node, where);
}

// The end condition an action has when the file gives no `until`.
EndCondition DefaultEnd(const ActionParams& params) {
  if (std::holds_alternative<FreeNavigationAction>(params)) {
    return {EndConditionKind::kGoalReached, 0};
  }
  if (const auto* dock = std::get_if<DockAction>(&params)) {
    return {dock->target == DockTarget::kCharger ? EndConditionKind::kChargerContact
                                                 : EndConditionKind::kGoalReached,
            0};
  }
  return {EndConditionKind::kDistance, 0};
}

absl::StatusOr<EndCondition> ParseUntil(const YAML::Node& node, const std::string& where) {
  const std::string field = absl::StrCat(where, ": until");
  if (node.IsMap()) {
    RETURN_IF_ERROR(internal::CheckKnownKeys(node, {"marker"}, field));
    if (!Has(node, "marker")) {
      return absl::InvalidArgumentError(absl::StrCat(field, ": expected {marker: <id>}"));
    }
    ASSIGN_OR_RETURN(const int marker_id, internal::AsInt(node["marker"], field + ": marker"));
    return EndCondition{EndConditionKind::kMarkerDetected, marker_id};
  }
  if (!node.IsScalar()) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": expected a condition name or {marker: <id>}"));
  }
  const std::string& name = node.Scalar();
  if (name == "marker" || name == "marker_detected") {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": a marker end needs its id, write {marker: <id>}"));
  }
  absl::StatusOr<EndConditionKind> kind = ParseEndConditionKind(name);
  if (!kind.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": ", kind.status().message()));
  }
  return EndCondition{*kind, 0};
}

absl::StatusOr<RouteAction> ParseAction(const YAML::Node& node, size_t index) {
  const std::string prefix = absl::StrCat("actions[", index, "]");
  if (!node.IsMap()) {
    return absl::InvalidArgumentError(
        absl::StrCat(prefix, ": expected a mapping such as {straight: {distance: 1}}"));
  }
  ASSIGN_OR_RETURN(const std::vector<std::string> keys, internal::MapKeys(node, prefix));
  std::vector<std::string> types;
  std::vector<std::string> others;
  for (const std::string& key : keys) {
    if (IsActionType(key)) {
      types.push_back(key);
    } else if (key != kUntilKey) {
      others.push_back(key);
    }
  }
  if (types.empty()) {
    if (!others.empty()) {
      return absl::InvalidArgumentError(absl::StrCat(prefix, ": unknown action type '",
                                                     others.front(), "' (expected one of ",
                                                     absl::StrJoin(kActionTypes, ", "), ")"));
    }
    return absl::InvalidArgumentError(absl::StrCat(prefix, ": missing the action type"));
  }
  if (types.size() > 1) {
    return absl::InvalidArgumentError(
        absl::StrCat(prefix, ": more than one action type ('", absl::StrJoin(types, "', '"), "')"));
  }
  const std::string where = absl::StrCat(prefix, " (", types.front(), ")");
  if (!others.empty()) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": unknown key '", others.front(), "'"));
  }
  RouteAction action;
  ASSIGN_OR_RETURN(action.params, ParseParams(types.front(), node[types.front()], where));
  action.end = DefaultEnd(action.params);
  if (node[kUntilKey].IsDefined()) {
    ASSIGN_OR_RETURN(action.end, ParseUntil(node[kUntilKey], where));
  }
  return action;
}

absl::StatusOr<Route> RouteFromNode(const YAML::Node& root) {
  if (!root.IsMap()) return absl::InvalidArgumentError("route YAML: expected a mapping at the top");
  RETURN_IF_ERROR(internal::CheckKnownKeys(root, {"name", "map", "actions"}, "route YAML"));
  Route route;
  if (!Has(root, "name")) return absl::InvalidArgumentError("route YAML: missing 'name'");
  ASSIGN_OR_RETURN(route.name, internal::AsString(root["name"], "name"));
  if (Has(root, "map")) {
    ASSIGN_OR_RETURN(route.map_id, internal::AsString(root["map"], "map"));
  }
  const YAML::Node actions = root["actions"];
  if (!actions.IsDefined() || actions.IsNull()) {
    return absl::InvalidArgumentError("route YAML: missing 'actions'");
  }
  if (!actions.IsSequence()) return absl::InvalidArgumentError("actions: expected a list");
  for (size_t i = 0; i < actions.size(); ++i) {
    ASSIGN_OR_RETURN(RouteAction action, ParseAction(actions[i], i));
    route.actions.push_back(std::move(action));
  }
  RETURN_IF_ERROR(route.Validate());
  return route;
}

// ---------------------------------------------------------------------------------------------
// Writing

// "<stem>_deg: <degrees>" when the degrees read back to exactly `rad`, else "<stem>_rad: ...".
std::string AngleField(absl::string_view stem, double rad) {
  const std::string deg_text = FormatDouble(RadToDeg(rad));
  if (DegToRad(std::strtod(deg_text.c_str(), nullptr)) == rad) {
    return absl::StrCat(stem, "_deg: ", deg_text);
  }
  return absl::StrCat(stem, "_rad: ", FormatDouble(rad));
}

struct ParamsWriter {
  std::string operator()(const TurnAction& turn) const {
    return absl::StrCat("turn: {", AngleField("angle", turn.angle_rad),
                        ", yaw_rate: ", FormatDouble(turn.yaw_rate_radps), "}");
  }
  std::string operator()(const StraightAction& straight) const {
    return absl::StrCat("straight: {distance: ", FormatDouble(straight.distance_m),
                        ", speed: ", FormatDouble(straight.speed_mps), "}");
  }
  std::string operator()(const MoveAction& move) const {
    return absl::StrCat("move: {dx: ", FormatDouble(move.dx_m), ", dy: ", FormatDouble(move.dy_m),
                        ", speed: ", FormatDouble(move.speed_mps), "}");
  }
  std::string operator()(const FreeNavigationAction& navigation) const {
    std::string text = "free_navigation: {";
    if (!navigation.waypoints_m.empty()) {
      std::vector<std::string> points;
      for (size_t i = 0; i < navigation.waypoints_m.size(); ++i) {
        const Eigen::Vector2d& point = navigation.waypoints_m[i];
        const std::optional<double> yaw = navigation.WaypointYaw(i);
        points.push_back(absl::StrCat("[", FormatDouble(point.x()), ", ", FormatDouble(point.y()),
                                      yaw ? absl::StrCat(", ", FormatDouble(RadToDeg(*yaw))) : "",
                                      "]"));
      }
      absl::StrAppend(&text, "waypoints: [", absl::StrJoin(points, ", "), "], ");
    }
    absl::StrAppend(&text, "goal: {x: ", FormatDouble(navigation.goal.x_m()),
                    ", y: ", FormatDouble(navigation.goal.y_m()), ", ",
                    AngleField("yaw", navigation.goal.yaw_rad()),
                    "}, speed: ", FormatDouble(navigation.speed_mps), "}");
    return text;
  }
  std::string operator()(const FenceNavigationAction& fence) const {
    return absl::StrCat("fence_navigation: {side: ", fence.side == Side::kLeft ? "left" : "right",
                        ", fence_distance: ", FormatDouble(fence.fence_distance_m),
                        ", distance: ", FormatDouble(fence.distance_m),
                        ", speed: ", FormatDouble(fence.speed_mps), "}");
  }
  std::string operator()(const StripeNavigationAction& stripe) const {
    return absl::StrCat("stripe_navigation: {stripe: ", stripe.stripe_id,
                        ", distance: ", FormatDouble(stripe.distance_m),
                        ", speed: ", FormatDouble(stripe.speed_mps), "}");
  }
  std::string operator()(const DockAction& dock) const {
    std::string text = absl::StrCat("dock: {target: ",
                                    dock.target == DockTarget::kCharger ? "charger" : "trolley");
    if (!dock.target_id.empty()) {
      absl::StrAppend(&text, ", target_id: ", internal::YamlScalar(dock.target_id));
    }
    return text + "}";
  }
  std::string operator()(const UndockAction&) const { return "undock: {}"; }
};

std::string UntilText(const EndCondition& end) {
  if (end.kind == EndConditionKind::kMarkerDetected) {
    return absl::StrCat("{marker: ", end.marker_id, "}");
  }
  return std::string(EndConditionKindName(end.kind));
}

}  // namespace

absl::StatusOr<Route> ParseRouteYaml(std::string_view yaml_text) {
  ASSIGN_OR_RETURN(const YAML::Node root, internal::LoadYaml(yaml_text, "route YAML"));
  try {
    return RouteFromNode(root);
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat("route YAML: ", e.what()));
  }
}

std::string RouteToYaml(const Route& route) {
  std::string text = absl::StrCat("name: ", internal::YamlScalar(route.name), "\n");
  if (!route.map_id.empty()) {
    absl::StrAppend(&text, "map: ", internal::YamlScalar(route.map_id), "\n");
  }
  if (route.actions.empty()) return text + "actions: []\n";
  absl::StrAppend(&text, "actions:\n");
  for (const RouteAction& action : route.actions) {
    absl::StrAppend(&text, "  - ", std::visit(ParamsWriter{}, action.params), "\n");
    if (action.end.kind != DefaultEnd(action.params).kind) {
      absl::StrAppend(&text, "    until: ", UntilText(action.end), "\n");
    }
  }
  return text;
}

absl::StatusOr<Route> LoadRoute(const std::string& path) {
  ASSIGN_OR_RETURN(const std::string text, internal::ReadFileToString(path));
  absl::StatusOr<Route> route = ParseRouteYaml(text);
  if (!route.ok()) {
    return absl::Status(route.status().code(), absl::StrCat(path, ": ", route.status().message()));
  }
  return route;
}

absl::Status SaveRoute(const Route& route, const std::string& path) {
  RETURN_IF_ERROR(route.Validate());
  return internal::WriteStringToFile(path, RouteToYaml(route));
}

}  // namespace fleetnav
