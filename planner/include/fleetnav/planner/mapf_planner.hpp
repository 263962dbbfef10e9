#pragma once

#include <cstdint>
#include <stop_token>

#include "absl/status/statusor.h"
#include "fleetnav/planner/mapf.hpp"

namespace fleetnav::planner {

/// Parameters of MapfPlanner.
struct MapfPlannerParams {
  enum class Selection { kAuto, kLacam, kEecbs };
  Selection selection = Selection::kAuto;
  double time_limit_s = 1.0;  ///< total budget, > 0
  uint64_t seed = 0;          ///< passed to every randomized solver
  bool anytime = true;        ///< LaCAM refines while time remains
  /// kAuto tries EECBS first when there are at most this many agents.
  int eecbs_max_agents = 100;
  /// Share of the budget EECBS gets under kAuto before LaCAM takes the rest, in (0, 1].
  double eecbs_budget_fraction = 0.95;
  double eecbs_suboptimality = 1.2;  ///< w of EECBS, ≥ 1

  absl::Status Validate() const;
};

/// The multi-robot planner entry point: picks a solver for the instance and the budget and
/// returns the best plan found. Selection kAuto: up to `eecbs_max_agents` agents, a LaCAM plan
/// (not anytime, usually milliseconds) is found first as the fallback, then EECBS
/// (EecbsSolver, bounded-suboptimal) runs until `eecbs_budget_fraction` of the budget is used,
/// and if it does not finish LaCAM* refines with the rest; the cheapest plan wins. For more
/// agents LaCAM* (LacamSolver) runs alone and refines until the budget ends. Duplicate goals
/// are refused as InvalidArgument (two robots cannot both rest on one vertex). Stateless
/// between calls; one Solve at a time per object.
class MapfPlanner {
 public:
  explicit MapfPlanner(const MapfPlannerParams& params) : params_(params) {}
  absl::StatusOr<MapfResult> Solve(const MapfInstance& instance, std::stop_token stop = {});

 private:
  MapfPlannerParams params_;
};

}  // namespace fleetnav::planner
