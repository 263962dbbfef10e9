#pragma once

#include <cstdint>
#include <stop_token>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/planner/mapf/mapf.hpp"
#include "fleetnav/planner/mapf/mapf_solver.hpp"

namespace fleetnav::planner {

/// Parameters of EecbsSolver.
struct EecbsParams {
  double suboptimality = 1.1;         ///< w ≥ 1: the plan's sum of costs ≤ w × the optimal one
  int max_high_level_nodes = 200000;  ///< search cap (a memory bound), > 0

  absl::Status Validate() const;
};

/// Bounded-suboptimal conflict-based search in the style of EECBS (Li, Ruml and Koenig,
/// "EECBS: A Bounded-Suboptimal Search for Multi-Agent Path Finding", AAAI 2021), built on CBS
/// (Sharon et al., AIJ 2015), in its ECBS form (Barer et al., SoCS 2014). The high level is a
/// focal search over constraint-tree nodes: among the open nodes whose sum of costs is within
/// w of the lowest open lower bound, it expands the node with the fewest pairwise conflicts.
/// The low level is SIPP with the soft-conflict intervals of SIPPS (SippPlanner): the node's
/// vertex and edge constraints are hard reservations, the other agents' current paths soft
/// ones; it is focal with the same w (fewest conflicts first among arrivals within w of the
/// best) and reports its lowest open f as the agent's lower bound. The returned plan's sum of
/// costs is at most w times the optimum. Not done from EECBS: explicit estimation (its third
/// list and online cost learning) and conflict prioritisation. One Solve at a time.
class EecbsSolver : public MapfSolver {
 public:
  explicit EecbsSolver(const EecbsParams& params) : params_(params) {}

  std::string Name() const override { return "eecbs"; }
  double SuboptimalityBound() const override { return params_.suboptimality; }
  /// ResourceExhausted at the node cap; NotFound when the constraint tree is exhausted.
  absl::StatusOr<MapfResult> Solve(const MapfInstance& instance, const MapfStopCondition& stop,
                                   const MapfPlanObserver& on_plan = nullptr) override;

 private:
  EecbsParams params_;
};

}  // namespace fleetnav::planner
