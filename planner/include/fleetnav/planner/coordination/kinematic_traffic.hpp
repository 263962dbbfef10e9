#pragma once

#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/traffic_plan.hpp"

namespace fleetnav::planner {

/// Whether PlanPaths should plan these robots with headings and footprints
/// (PlanKinematicTraffic) rather than as points on one coarse grid: at least one robot drives
/// differentially (turns in place; the Lely must not reverse) and the fleet is small enough for
/// conflict-based search.
bool UseKinematicTraffic(const std::vector<RobotModel>& models);

/// PlanPaths for heading-constrained and mixed fleets (PlanKinematicMapf): the map is
/// coarsened to cells as wide as the smallest robot; each robot covers the cells its
/// circumscribed disc touches (so turning in place never sweeps more), differential-drive robots
/// carry a heading and reverse only if their model may (Ackermann and omni robots move in any
/// grid direction, as they cannot turn in place or need not), and the
/// plan is compiled into a KinematicDependencyGraph. Timed poses face the robot's heading.
/// InvalidArgument when a start or goal does not fit the robot on this grid or two goals
/// overlap, DeadlineExceeded when no plan is found in time: the caller then plans on the
/// coarse point-robot grid instead.
absl::StatusOr<TrafficPlan> PlanKinematicTraffic(const OccupancyGrid& grid,
                                                 const std::vector<TrafficAgent>& agents,
                                                 const std::vector<RobotModel>& models,
                                                 double time_limit_s);

}  // namespace fleetnav::planner
