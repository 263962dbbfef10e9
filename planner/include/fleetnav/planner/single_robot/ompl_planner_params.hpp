#pragma once

#include <cstdint>

#include "absl/status/status.h"

namespace fleetnav::planner {

/// Parameters of the OMPL-based planners (OmplOmniPlanner, OmplReedsSheppPlanner).
struct OmplPlannerParams {
  /// Seeds the planner's state sampler and RRTConnect's own generator for every Plan() call,
  /// so that one seed gives one path (the search is otherwise deterministic). > 0.
  uint32_t seed = 1;
  /// RRTConnect's maximum extension in the space's distance; 0: OMPL's default (a fifth of the
  /// space's largest extent).
  double range = 0.0;
  /// Motion checks sample the footprint test at least this often, in cells of the costmap: the
  /// position and the footprint's farthest corner move at most this far between two checks.
  /// In (0, 1].
  double motion_check_resolution_cells = 0.5;
  bool simplify = true;           ///< shorten the raw RRTConnect path (deterministic)
  bool allow_approximate = true;  ///< return the start-tree pose closest to the goal on timeout

  absl::Status Validate() const;
};

}  // namespace fleetnav::planner
