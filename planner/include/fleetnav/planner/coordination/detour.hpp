#pragma once

#include <Eigen/Core>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/grid/swept_cells.hpp"

namespace fleetnav::planner {

/// How PlanDetour plans and thins its path.
struct DetourParams {
  double padding_m = 0.1;  ///< kept round the footprint, as the agent's free navigation
  double max_leg_m = 6.0;  ///< the longest straight line between two waypoints
  /// Each leg's search ends after this many lattice expansions (about 0.5 s on an idle core),
  /// so that a way round is the same however busy the machine is (a run replays exactly).
  int max_expansions = 300'000;
  double time_limit_s = 30.0;  ///< each leg's: a safety net; max_expansions ends a search first
  absl::Status Validate() const;
};

/// A free-navigation action planned around robots that stand (issue 35's coordinated paths,
/// first part: space, not yet time): the map with the cells of `blocked` (CellSets of side
/// `cell_m`, grown as the caller wants the robot kept off them) marked occupied, the robot's
/// own navigation planner (NavigationPlannerParams) from `from` through the action's waypoints
/// to its goal, and the path thinned to the waypoints the robot then drives through: its
/// corners, where a straight line on would come nearer the obstacles than the path does (the
/// action's own waypoints kept). Few waypoints keep the robot's and fleetnavd's planning
/// through them cheap (a search per leg). Blocked cells under the robot's own
/// footprint at `from` are left free (a robot standing close beside it must not make it start
/// inside an obstacle). Errors: InvalidArgument for bad params or a pose off the map,
/// NotFound when no way around them reaches the goal (the message names what blocks it).
/// Pure function of its inputs.
absl::StatusOr<std::vector<Eigen::Vector2d>> PlanDetour(const OccupancyGrid& grid,
                                                        const RobotModel& model,
                                                        const std::vector<const CellSet*>& blocked,
                                                        double cell_m, const Pose2& from,
                                                        const FreeNavigationAction& action,
                                                        const DetourParams& params = {});

/// `poses` (a path in the map frame) thinned to waypoints: from the start, each waypoint the
/// farthest pose that a straight line reaches keeping as far off the costmap's obstacles
/// (grid frame `map_origin`) as the path between does, within half a cell, and at most
/// params.max_leg_m long; each of `keep` (where the poses first pass within 0.25 m of it) is
/// kept and never skipped. The start and the last pose (the goal) are left out.
std::vector<Eigen::Vector2d> ThinToWaypoints(const std::vector<Pose2>& poses,
                                             const Costmap& costmap, const Pose2& map_origin,
                                             const DetourParams& params,
                                             const std::vector<Eigen::Vector2d>& keep = {});

}  // namespace fleetnav::planner
