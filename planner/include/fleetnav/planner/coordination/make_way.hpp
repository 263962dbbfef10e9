#pragma once

#include <Eigen/Core>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/grid/swept_cells.hpp"

namespace fleetnav::planner {

/// How far and how finely FindMakeWayPlace looks.
struct MakeWayParams {
  double max_distance_m = 15.0;   ///< over free floor from where the robot stands
  double candidate_step_m = 0.2;  ///< places are tried on a lattice this fine
  absl::Status Validate() const;
};

/// The robot that is to make way, and the floor it must keep off.
struct MakeWayRequestGeometry {
  Pose2 from_in_map;                         ///< where it stands
  std::vector<Eigen::Vector2d> footprint_m;  ///< its footprint (base_link), carrying its load
  double margin_m = 0.5;                     ///< grown round it, as traffic coordination does
  double cell_m = 0.2;                       ///< the cells of the CellSets below
  /// The floor others still need: their remaining swept actions, their end places, where other
  /// idle robots stand.
  std::vector<const CellSet*> keep_off;
  /// Where other robots stand now: the way to the place does not pass through them (its centre
  /// keeps half the footprint's smaller side plus `pass_margin_m` off these cells), so a robot
  /// is not sent past the one it waits for.
  std::vector<const CellSet*> impassable;
  double pass_margin_m = 0.0;  ///< as traffic coordination grows a moving robot's footprint
};

/// Where a robot that stands in other robots' way can wait instead ("robots make way", as Čáp,
/// Vokřínek and Kleiner's well-formed infrastructures need an end place off every other
/// robot's way): the place nearest by way over the floor (Dijkstra over the costmap's cells the
/// footprint fits in at some yaw and that keep clear of `impassable`, 8-connected, so the
/// place is one the robot can drive to without passing another)
/// where the footprint fits at the robot's yaw, or a quarter, half or three quarters of a turn
/// from it, and whose swept cells, grown by the margin and one cell more (the robot stops within
/// its goal tolerance of the place), meet none of `keep_off`. The costmap is
/// the map's (grid frame, origin `map_origin`); the answer is in the map frame. NotFound, naming
/// the place, when no such place lies within params.max_distance_m. Pure function of its inputs
/// (the costmap caches its footprint checks).
absl::StatusOr<Pose2> FindMakeWayPlace(Costmap& costmap, const Pose2& map_origin,
                                       const MakeWayRequestGeometry& request,
                                       const MakeWayParams& params = {});

}  // namespace fleetnav::planner
