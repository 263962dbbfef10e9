#pragma once

#include <Eigen/Core>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/planner/grid/swept_cells.hpp"

namespace fleetnav::planner {

/// How PlanDetour plans and thins its path.
struct DetourParams {
  double padding_m = 0.1;           ///< kept round the footprint, as the agent's free navigation
  double waypoint_spacing_m = 1.0;  ///< a waypoint each time the path has gone this far
  double time_limit_s = 0.5;        ///< for each leg's search
  absl::Status Validate() const;
};

/// A free-navigation action planned around robots that stand (issue 35's coordinated paths,
/// first part: space, not yet time): the map with the cells of `blocked` (CellSets of side
/// `cell_m`, grown as the caller wants the robot kept off them) marked occupied, the robot's
/// own navigation planner (NavigationPlannerParams) from `from` through the action's waypoints
/// to its goal, and the path thinned to waypoints `waypoint_spacing_m` apart (the action's own
/// waypoints kept) that the robot then drives through. Blocked cells under the robot's own
/// footprint at `from` are left free (a robot standing close beside it must not make it start
/// inside an obstacle). Errors: InvalidArgument for bad params or a pose off the map,
/// NotFound when no way around them reaches the goal (the message names what blocks it).
/// Pure function of its inputs.
absl::StatusOr<std::vector<Eigen::Vector2d>> PlanDetour(
    const OccupancyGrid& grid, const RobotModel& model, const std::vector<const CellSet*>& blocked,
    double cell_m, const Pose2& from, const FreeNavigationAction& action,
    const DetourParams& params = {});

/// `poses` thinned to points `spacing_m` apart along them (the first pose, the start, left out;
/// none within half the spacing of the last), keeping each of `keep` (in order, each where
/// the poses first pass within 0.25 m of it).
std::vector<Eigen::Vector2d> ThinToWaypoints(const std::vector<Pose2>& poses, double spacing_m,
                                             const std::vector<Eigen::Vector2d>& keep = {});

}  // namespace fleetnav::planner
