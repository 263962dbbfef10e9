#pragma once

#include <stop_token>

#include "absl/status/statusor.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/single_robot/ompl_planner_params.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"

namespace fleetnav::planner {

/// An omnidirectional planner on OMPL 1.5: SE2StateSpace bounded by the costmap, RRTConnect
/// (Kuffner and LaValle, ICRA 2000), then a deterministic simplification (OMPL's
/// PathSimplifier::collapseCloseVertices and a greedy shortcut). Poses are joined by straight
/// lines with the yaw interpolated along them (the omni platform translates and turns at once).
/// State validity is the costmap's footprint test; motions are tested so that no footprint
/// point moves more than `motion_check_resolution_cells` (default half a cell) between tests.
/// Seeds: OMPL 1.5.2 has no per-planner seed, only the process-wide ompl::RNG::setSeed that
/// works only before the first generator exists; this class instead seeds its own state
/// sampler and RRTConnect's generator from `params.seed` on every Plan() call, so a seed gives
/// one path without process-global state (the nearest-neighbour structure draws pivots from
/// OMPL's process generator, which does not change its exact answers). Exact results join the
/// goal pose itself; on timeout the start-tree branch closest to the goal is returned with
/// `exact = false` (or NotFound). Start or goal outside the map or in collision:
/// InvalidArgument. Holds a pointer to the costmap, which must outlive it. Not thread-safe.
class OmplOmniPlanner : public SingleRobotPlanner {
 public:
  OmplOmniPlanner(Costmap* costmap, const OmplPlannerParams& params)
      : costmap_(costmap), params_(params) {}
  absl::StatusOr<PathResult> Plan(const PathRequest& request, std::stop_token stop = {}) override;

 private:
  Costmap* costmap_;
  OmplPlannerParams params_;
};

}  // namespace fleetnav::planner
