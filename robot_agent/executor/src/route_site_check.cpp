#include "fleetnav/robot_agent/route_site_check.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/planner/coordination/route_prediction.hpp"
#include "fleetnav/planner/grid/costmap.hpp"

namespace fleetnav::agent {
namespace {

std::string Where(const RouteAction& action, size_t index) {
  return absl::StrCat("actions[", index, "] (", std::string(ActionTypeName(action.params)), ")");
}

/// True when a beam from `origin` along `angle_rad` meets an occupied cell within `range_m`
/// (sampled at a third of a cell).
bool BeamMeetsObstacle(const OccupancyGrid& map, const Eigen::Vector2d& origin, double angle_rad,
                       double range_m) {
  const Eigen::Vector2d direction(std::cos(angle_rad), std::sin(angle_rad));
  const double step_m = map.resolution_m() / 3.0;
  for (double s = 0.0; s <= range_m; s += step_m) {
    if (map.StateAtWorld(origin + direction * s) == CellState::kOccupied) return true;
  }
  return false;
}

/// Finds whether cell `to` is reachable from `from` over 8-connected cells whose distance to the
/// nearest obstacle is at least `clearance_m`.
class ClearanceGraph {
 public:
  ClearanceGraph(const planner::Costmap& costmap, double clearance_m)
      : costmap_(costmap), clearance_m_(clearance_m) {}

  bool Passable(int x, int y) const {
    return costmap_.InBounds(x, y) && !costmap_.IsObstacle(x, y) &&
           costmap_.DistanceToObstacle_m(x, y) >= clearance_m_;
  }

  bool Connected(int from_x, int from_y, int to_x, int to_y) const {
    const int w = costmap_.width();
    std::vector<uint8_t> seen(static_cast<size_t>(w) * costmap_.height(), 0);
    std::deque<std::pair<int, int>> open{{from_x, from_y}};
    seen[static_cast<size_t>(from_y) * w + from_x] = 1;
    while (!open.empty()) {
      const auto [x, y] = open.front();
      open.pop_front();
      if (x == to_x && y == to_y) return true;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx;
          const int ny = y + dy;
          if ((dx == 0 && dy == 0) || !Passable(nx, ny)) continue;
          uint8_t& s = seen[static_cast<size_t>(ny) * w + nx];
          if (s == 0) {
            s = 1;
            open.emplace_back(nx, ny);
          }
        }
      }
    }
    return false;
  }

 private:
  const planner::Costmap& costmap_;
  double clearance_m_;
};

absl::Status CheckFence(const FenceNavigationAction& fence, const RouteAction& action, size_t index,
                        const RouteContext& context, const planner::PredictedAction& predicted,
                        const RouteSiteCheckParams& params) {
  const SensorMount* mount =
      context.model.FindSensor(fence.side == Side::kLeft ? "ultrasonic_left" : "ultrasonic_right");
  if (mount == nullptr) return absl::OkStatus();  // CheckRoute refuses it
  const double range_m = fence.fence_distance_m + params.fence_search_margin_m;
  for (const Pose2& pose : predicted.poses) {
    const Pose2 sensor = pose * mount->pose_in_base;
    if (BeamMeetsObstacle(*context.map, sensor.translation(), sensor.yaw_rad(), range_m)) {
      return absl::OkStatus();
    }
  }
  const Pose2& from = predicted.poses.front();
  return absl::FailedPreconditionError(absl::StrFormat(
      "%s: no fence within %.2f m on the %s along the %.1f m leg from (%.2f, %.2f) on the map",
      Where(action, index), range_m, fence.side == Side::kLeft ? "left" : "right", fence.distance_m,
      from.x_m(), from.y_m()));
}

absl::Status CheckReachable(const FreeNavigationAction& nav, const RouteAction& action,
                            size_t index, const OccupancyGrid& map, planner::Costmap& costmap,
                            const Pose2& from) {
  const Pose2 grid_from_map = map.origin().Inverse();
  const auto cell = [&](const Eigen::Vector2d& p_in_map) {
    const Eigen::Vector2d p = grid_from_map.TransformPoint(p_in_map);
    return std::pair<int, int>{static_cast<int>(std::floor(p.x() / costmap.resolution_m())),
                               static_cast<int>(std::floor(p.y() / costmap.resolution_m()))};
  };
  // The disc inside the footprint, less the diagonal of a cell for the grid's rounding.
  const double clearance_m = costmap.inscribed_radius_m() - std::sqrt(2.0) * costmap.resolution_m();
  if (clearance_m <= 0.0) return absl::OkStatus();
  const ClearanceGraph graph(costmap, clearance_m);
  std::vector<Eigen::Vector2d> targets = nav.waypoints_m;
  targets.push_back(nav.goal.translation());
  Eigen::Vector2d leg_start = from.translation();
  for (const Eigen::Vector2d& target : targets) {
    const auto [sx, sy] = cell(leg_start);
    const auto [tx, ty] = cell(target);
    // A start or target wedged closer than the clearance (CheckRoute judges targets by the
    // footprint itself) cannot be judged this way: leave it to the planner.
    if (graph.Passable(sx, sy) && graph.Passable(tx, ty) && !graph.Connected(sx, sy, tx, ty)) {
      return absl::FailedPreconditionError(absl::StrFormat(
          "%s: (%.2f, %.2f) cannot be reached from (%.2f, %.2f): no way on the map is wide "
          "enough for the robot",
          Where(action, index), target.x(), target.y(), leg_start.x(), leg_start.y()));
    }
    leg_start = target;
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status RouteSiteCheckParams::Validate() const {
  if (!(std::isfinite(fence_search_margin_m) && fence_search_margin_m >= 0.0)) {
    return absl::InvalidArgumentError("fence_search_margin_m: must be finite and >= 0");
  }
  return absl::OkStatus();
}

absl::Status CheckRouteOnSite(const Route& route, const RouteContext& context,
                              const Pose2& start_in_map, const RouteSiteCheckParams& params,
                              int first_action) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (context.map == nullptr) return absl::OkStatus();
  const MarkerSet* markers = context.markers ? &*context.markers : nullptr;
  std::optional<planner::Costmap> costmap;
  Pose2 pose = start_in_map;
  for (size_t i = static_cast<size_t>(std::max(first_action, 0)); i < route.actions.size(); ++i) {
    const RouteAction& action = route.actions[i];
    Route one;
    one.actions = {action};
    absl::StatusOr<std::vector<planner::PredictedAction>> predicted =
        planner::PredictRoute(one, pose, markers, nullptr, context.map->origin());
    if (!predicted.ok() || predicted->empty()) return absl::OkStatus();
    const planner::PredictedAction& leg = predicted->front();
    if (const auto* fence = std::get_if<FenceNavigationAction>(&action.params)) {
      if (absl::Status s = CheckFence(*fence, action, i, context, leg, params); !s.ok()) return s;
    }
    if (const auto* nav = std::get_if<FreeNavigationAction>(&action.params)) {
      if (!costmap) {
        absl::StatusOr<planner::Costmap> built =
            planner::Costmap::Build(*context.map, context.model.footprint_m, {});
        if (!built.ok()) return built.status();
        costmap = *std::move(built);
      }
      if (absl::Status s = CheckReachable(*nav, action, i, *context.map, *costmap, pose); !s.ok()) {
        return s;
      }
    }
    // Where an action that ends on a marker or on the charger contact leaves the robot is not
    // known before it drives: the rest cannot be judged from here.
    if (action.end.kind == EndConditionKind::kMarkerDetected ||
        action.end.kind == EndConditionKind::kChargerContact) {
      return absl::OkStatus();
    }
    pose = leg.poses.back();
  }
  return absl::OkStatus();
}

}  // namespace fleetnav::agent
