#include "fleetnav/planner/coordination/detour.hpp"

#include <cmath>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/planner/coordination/route_prediction.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"

namespace fleetnav::planner {
namespace {

constexpr int8_t kOccupied = 100;

/// Marks the grid cells whose centres lie in a cell of `blocked`, except those under the
/// robot's own footprint, `own`.
void MarkBlocked(OccupancyGrid& grid, const std::vector<const CellSet*>& blocked, double cell_m,
                 const CellSet& own) {
  const double step_m = grid.resolution_m();
  for (const CellSet* set : blocked) {
    if (set == nullptr) continue;
    for (const Eigen::Vector2d& centre : set->CellCentres(cell_m)) {
      if (own.ContainsPoint(centre, cell_m)) continue;
      // Grid cells across the square, sampled at the grid's resolution.
      for (double dx = -0.5 * cell_m + 0.5 * step_m; dx < 0.5 * cell_m; dx += step_m) {
        for (double dy = -0.5 * cell_m + 0.5 * step_m; dy < 0.5 * cell_m; dy += step_m) {
          if (std::optional<CellIndex> at = grid.WorldToCell(centre + Eigen::Vector2d(dx, dy))) {
            grid.SetValue(*at, kOccupied);
          }
        }
      }
    }
  }
}

/// Whether the goal's cell can be reached from the start's over cells where at least the
/// footprint's inscribed circle fits (a necessary condition, and cheap: without it a search
/// with no way round the robots spends its whole time limit).
bool MaybeReachable(const Costmap& costmap, const Pose2& start_in_grid, const Pose2& goal_in_grid) {
  const double res_m = costmap.resolution_m();
  const auto cell = [&](const Pose2& p) {
    return std::make_pair(static_cast<int>(std::floor(p.x_m() / res_m)),
                          static_cast<int>(std::floor(p.y_m() / res_m)));
  };
  const auto [sx, sy] = cell(start_in_grid);
  const auto [gx, gy] = cell(goal_in_grid);
  if (!costmap.InBounds(sx, sy) || !costmap.InBounds(gx, gy)) return false;
  // Half a cell of slack: distances are between cell centres.
  const double fits_m = costmap.inscribed_radius_m() - 0.5 * res_m;
  const int width = costmap.width();
  std::vector<uint8_t> seen(static_cast<size_t>(width) * costmap.height(), 0);
  std::vector<int> open{sy * width + sx};
  seen[open.front()] = 1;
  while (!open.empty()) {
    const int index = open.back();
    open.pop_back();
    const int x = index % width;
    const int y = index / width;
    if (x == gx && y == gy) return true;
    constexpr int kDx[4] = {1, -1, 0, 0};
    constexpr int kDy[4] = {0, 0, 1, -1};
    for (int k = 0; k < 4; ++k) {
      const int nx = x + kDx[k];
      const int ny = y + kDy[k];
      if (!costmap.InBounds(nx, ny)) continue;
      const int n = ny * width + nx;
      if (seen[n] != 0 || costmap.DistanceToObstacle_m(nx, ny) < fits_m) continue;
      seen[n] = 1;
      open.push_back(n);
    }
  }
  return false;
}

}  // namespace

absl::Status DetourParams::Validate() const {
  if (!(std::isfinite(padding_m) && padding_m >= 0.0)) {
    return absl::InvalidArgumentError("padding_m: must be finite and >= 0");
  }
  if (!(std::isfinite(waypoint_spacing_m) && waypoint_spacing_m > 0.0)) {
    return absl::InvalidArgumentError("waypoint_spacing_m: must be finite and > 0");
  }
  if (!(std::isfinite(time_limit_s) && time_limit_s > 0.0)) {
    return absl::InvalidArgumentError("time_limit_s: must be finite and > 0");
  }
  return absl::OkStatus();
}

std::vector<Eigen::Vector2d> ThinToWaypoints(const std::vector<Pose2>& poses, double spacing_m,
                                             const std::vector<Eigen::Vector2d>& keep) {
  std::vector<Eigen::Vector2d> out;
  if (poses.size() < 2) return out;
  const Eigen::Vector2d end = poses.back().translation();
  size_t next_keep = 0;
  double since_m = 0.0;
  for (size_t i = 1; i < poses.size(); ++i) {
    const Eigen::Vector2d p = poses[i].translation();
    since_m += (p - poses[i - 1].translation()).norm();
    if (next_keep < keep.size() && (p - keep[next_keep]).norm() <= 0.25) {
      out.push_back(keep[next_keep++]);
      since_m = 0.0;
      continue;
    }
    if (since_m >= spacing_m && (end - p).norm() >= 0.5 * spacing_m) {
      out.push_back(p);
      since_m = 0.0;
    }
  }
  // Waypoints the path never came near (it cannot miss them: it was planned through them).
  while (next_keep < keep.size()) out.push_back(keep[next_keep++]);
  return out;
}

absl::StatusOr<std::vector<Eigen::Vector2d>> PlanDetour(
    const OccupancyGrid& grid, const RobotModel& model, const std::vector<const CellSet*>& blocked,
    double cell_m, const Pose2& from, const FreeNavigationAction& action,
    const DetourParams& params) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (!(std::isfinite(cell_m) && cell_m > 0.0)) {
    return absl::InvalidArgumentError("cell_m: must be finite and > 0");
  }
  if (!from.IsFinite() || !grid.ContainsWorld(from.translation())) {
    return absl::InvalidArgumentError(absl::StrFormat(
        "the robot at (%.2f, %.2f) is outside the map", from.x_m(), from.y_m()));
  }
  OccupancyGrid marked = grid;
  const CellSet own = CellSet::Sweep({from}, model.footprint_m, params.padding_m + cell_m, cell_m);
  MarkBlocked(marked, blocked, cell_m, own);
  CostmapParams costmap_params;
  costmap_params.padding_m = params.padding_m;
  absl::StatusOr<Costmap> costmap = Costmap::Build(marked, model.footprint_m, costmap_params);
  if (!costmap.ok()) return costmap.status();
  const Pose2 grid_from_map = marked.origin().Inverse();
  for (const Eigen::Vector2d& target : action.waypoints_m) {
    if (!MaybeReachable(*costmap, grid_from_map * from,
                        grid_from_map * Pose2(target.x(), target.y(), 0.0))) {
      return absl::NotFoundError(absl::StrFormat(
          "no way round the robots that stand: waypoint (%.2f, %.2f) is cut off", target.x(),
          target.y()));
    }
  }
  if (!MaybeReachable(*costmap, grid_from_map * from, grid_from_map * action.goal)) {
    return absl::NotFoundError(
        absl::StrFormat("no way round the robots that stand: the goal (%.2f, %.2f) is cut off",
                        action.goal.x_m(), action.goal.y_m()));
  }
  absl::StatusOr<std::unique_ptr<SingleRobotPlanner>> planner =
      MakeSingleRobotPlanner(&*costmap, model, NavigationPlannerParams(model));
  if (!planner.ok()) return planner.status();
  absl::StatusOr<WaypointPath> path =
      PlanThroughWaypoints(**planner, marked.origin(), from, action.waypoints_m, action.goal,
                           params.time_limit_s, action.waypoint_yaws_rad);
  if (!path.ok()) {
    return absl::NotFoundError(absl::StrCat("no way round the robots that stand: ",
                                            path.status().message()));
  }
  return ThinToWaypoints(path->poses, params.waypoint_spacing_m, action.waypoints_m);
}

}  // namespace fleetnav::planner
