#pragma once

#include <cstdint>
#include <stop_token>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/planner/mapf.hpp"

namespace fleetnav::planner {

/// Parameters of EecbsSolver.
struct EecbsParams {
  double suboptimality = 1.1;         ///< w ≥ 1: the plan's sum of costs ≤ w × the optimal one
  double time_limit_s = 1.0;          ///< wall-clock budget, > 0
  int max_high_level_nodes = 200000;  ///< search cap (a memory bound), > 0

  absl::Status Validate() const;
};

/// Bounded-suboptimal conflict-based search in the style of EECBS (Li, Ruml and Koenig,
/// "EECBS: A Bounded-Suboptimal Search for Multi-Agent Path Finding", AAAI 2021), built on CBS
/// (Sharon et al., AIJ 2015). The high level is a focal search over constraint-tree nodes:
/// among the nodes whose sum of costs is within w of the lowest open one, it expands the node
/// with the fewest pairwise conflicts. The low level is an optimal space-time A* with the
/// node's vertex and edge constraints as reservations; among equally short paths it prefers
/// the one with the fewest conflicts with the other agents' current paths (a conflict-avoidance
/// table). Because every low-level path is optimal under its constraints, the open node with
/// the lowest cost bounds the optimum from below and the returned plan's sum of costs is at
/// most w times the optimum. One Solve at a time per object.
class EecbsSolver {
 public:
  EecbsSolver(const MapfInstance& instance, const EecbsParams& params);

  /// Errors: InvalidArgument (bad instance or params), DeadlineExceeded (no plan within the
  /// budget), Cancelled (stop requested), ResourceExhausted (node cap), NotFound (no plan).
  absl::StatusOr<MapfResult> Solve(std::stop_token stop = {});

 private:
  MapfInstance instance_;
  EecbsParams params_;
};

}  // namespace fleetnav::planner
