#include "fleetnav/planner/coordination/detour.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/planner/coordination/route_prediction.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/grid/free_space_regions.hpp"
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

}  // namespace

absl::Status DetourParams::Validate() const {
  if (!(std::isfinite(padding_m) && padding_m >= 0.0)) {
    return absl::InvalidArgumentError("padding_m: must be finite and >= 0");
  }
  if (!(std::isfinite(max_leg_m) && max_leg_m > 0.0)) {
    return absl::InvalidArgumentError("max_leg_m: must be finite and > 0");
  }
  if (!(std::isfinite(time_limit_s) && time_limit_s > 0.0)) {
    return absl::InvalidArgumentError("time_limit_s: must be finite and > 0");
  }
  if (max_expansions <= 0) return absl::InvalidArgumentError("max_expansions: must be > 0");
  return absl::OkStatus();
}

std::vector<Eigen::Vector2d> ThinToWaypoints(const std::vector<Pose2>& poses,
                                             const Costmap& costmap, const Pose2& map_origin,
                                             const DetourParams& params,
                                             const std::vector<Eigen::Vector2d>& keep) {
  std::vector<Eigen::Vector2d> out;
  if (poses.size() < 2) return out;
  const double res_m = costmap.resolution_m();
  const Pose2 grid_from_map = map_origin.Inverse();
  // Clearance of a point of the map: the distance from its cell to the nearest obstacle.
  const auto clearance_m = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d g = grid_from_map.TransformPoint(p);
    const int x = static_cast<int>(std::floor(g.x() / res_m));
    const int y = static_cast<int>(std::floor(g.y() / res_m));
    return costmap.InBounds(x, y) ? costmap.DistanceToObstacle_m(x, y) : 0.0;
  };
  std::vector<double> along(poses.size(), 0.0);  // the path's own clearance at each pose
  for (size_t i = 0; i < poses.size(); ++i) along[i] = clearance_m(poses[i].translation());
  // Whether the straight line from pose i to pose j keeps as far off obstacles as the path
  // between them does (within half a cell), and is no longer than the longest leg.
  const auto straight = [&](size_t i, size_t j) {
    const Eigen::Vector2d a = poses[i].translation();
    const Eigen::Vector2d b = poses[j].translation();
    if ((b - a).norm() > params.max_leg_m) return false;
    const double needed_m = *std::min_element(along.begin() + static_cast<std::ptrdiff_t>(i),
                                              along.begin() + static_cast<std::ptrdiff_t>(j) + 1) -
                            0.5 * res_m;
    const int samples = static_cast<int>(std::ceil((b - a).norm() / (0.5 * res_m)));
    for (int k = 1; k < samples; ++k) {
      if (clearance_m(a + (b - a) * (static_cast<double>(k) / samples)) < needed_m) return false;
    }
    return true;
  };
  // The action's own waypoints, each where the poses first pass within 0.25 m of it.
  std::vector<size_t> kept_at;
  for (size_t i = 0, next = 0; i < poses.size() && next < keep.size(); ++i) {
    if ((poses[i].translation() - keep[next]).norm() <= 0.25) {
      kept_at.push_back(i);
      ++next;
    }
  }
  // From each waypoint, the farthest pose reached in a straight line (never past a kept one).
  size_t from = 0;
  size_t next_kept = 0;
  const size_t last = poses.size() - 1;
  while (from < last) {
    const size_t limit = next_kept < kept_at.size() ? kept_at[next_kept] : last;
    size_t to = from + 1;
    while (to < limit && straight(from, to + 1)) ++to;
    if (to == limit && next_kept < kept_at.size()) {
      out.push_back(keep[next_kept++]);
    } else if (to < last) {
      out.push_back(poses[to].translation());
    }
    from = to;
  }
  while (next_kept < kept_at.size()) out.push_back(keep[next_kept++]);
  return out;
}

absl::StatusOr<std::vector<Eigen::Vector2d>> PlanDetour(const OccupancyGrid& grid,
                                                        const RobotModel& model,
                                                        const std::vector<const CellSet*>& blocked,
                                                        double cell_m, const Pose2& from,
                                                        const FreeNavigationAction& action,
                                                        const DetourParams& params) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (!(std::isfinite(cell_m) && cell_m > 0.0)) {
    return absl::InvalidArgumentError("cell_m: must be finite and > 0");
  }
  if (!from.IsFinite() || !grid.ContainsWorld(from.translation())) {
    return absl::InvalidArgumentError(
        absl::StrFormat("the robot at (%.2f, %.2f) is outside the map", from.x_m(), from.y_m()));
  }
  OccupancyGrid marked = grid;
  const CellSet own = CellSet::Sweep({from}, model.footprint_m, params.padding_m + cell_m, cell_m);
  MarkBlocked(marked, blocked, cell_m, own);
  CostmapParams costmap_params;
  costmap_params.padding_m = params.padding_m;
  absl::StatusOr<Costmap> costmap = Costmap::Build(marked, model.footprint_m, costmap_params);
  if (!costmap.ok()) return costmap.status();
  const Pose2 grid_from_map = marked.origin().Inverse();
  // Without a way wide enough for the robot's inscribed circle there is none for the robot: a
  // search would spend its whole time limit to find that.
  const FreeSpaceRegions regions(*costmap);
  const Eigen::Vector2d from_in_grid = (grid_from_map * from).translation();
  // A robot standing nearer an obstacle than its padded inscribed circle drives off from there.
  const double near_m = params.padding_m + 2.0 * grid.resolution_m();
  for (const Eigen::Vector2d& target : action.waypoints_m) {
    if (!regions.Connected(from_in_grid, grid_from_map.TransformPoint(target), near_m)) {
      return absl::NotFoundError(
          absl::StrFormat("no way round the robots that stand: waypoint (%.2f, %.2f) is cut off",
                          target.x(), target.y()));
    }
  }
  if (!regions.Connected(from_in_grid, (grid_from_map * action.goal).translation(), near_m)) {
    return absl::NotFoundError(
        absl::StrFormat("no way round the robots that stand: the goal (%.2f, %.2f) is cut off",
                        action.goal.x_m(), action.goal.y_m()));
  }
  SingleRobotPlannerParams planner_params = NavigationPlannerParams(model);
  planner_params.lattice.max_expansions =
      std::min(planner_params.lattice.max_expansions, params.max_expansions);
  absl::StatusOr<std::unique_ptr<SingleRobotPlanner>> planner =
      MakeSingleRobotPlanner(&*costmap, model, planner_params);
  if (!planner.ok()) return planner.status();
  absl::StatusOr<WaypointPath> path =
      PlanThroughWaypoints(**planner, marked.origin(), from, action.waypoints_m, action.goal,
                           params.time_limit_s, action.waypoint_yaws_rad);
  if (!path.ok()) {
    return absl::NotFoundError(
        absl::StrCat("no way round the robots that stand: ", path.status().message()));
  }
  return ThinToWaypoints(path->poses, *costmap, marked.origin(), params, action.waypoints_m);
}

}  // namespace fleetnav::planner
