#pragma once

#include <cstdint>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "fleetnav/planner/grid/grid_graph.hpp"
#include "fleetnav/planner/mapf/constraint_table.hpp"

namespace fleetnav::planner {

/// One single-agent query of SippPlanner.
struct SippRequest {
  int start = 0;
  int goal = 0;
  int start_step = 0;          ///< the step at which the agent is at `start`
  double suboptimality = 1.0;  ///< focal bound w ≥ 1 on the arrival step
  int64_t max_expansions = 2'000'000;
  /// Never enter a vertex that was reserved the step before (never follow another robot), so
  /// no rotation can include the path.
  bool no_following = false;
};

/// A path found by SippPlanner: path[k] is the vertex at step start_step + k, ending with the
/// arrival at the goal, where the agent can then stay for ever.
struct SippResult {
  std::vector<int> path;
  int arrival_step = 0;
  int lower_bound_step = 0;  ///< no path under the hard reservations arrives earlier
  int conflicts = 0;         ///< soft reservations the path runs into
  int64_t expanded = 0;
};

/// Safe Interval Path Planning (Phillips and Likhachev, ICRA 2011) with the soft-conflict
/// intervals and focal search of SIPPS (Li et al., AAAI 2022): states are (vertex, safe
/// interval) with the earliest arrival step, so waits cost nothing to represent and long
/// horizons stay cheap. Hard reservations of the ConstraintTable are never violated. Among the
/// states whose f = arrival + distance-to-goal is within w of the lowest open f (FOCAL), the
/// one with the fewest soft conflicts is expanded first; with w = 1 the arrival is optimal
/// under the hard reservations and conflicts break ties. The goal counts as reached only where
/// the agent may stay for ever; soft reservations of the goal after the arrival count as
/// conflicts. Reusable across queries; not thread-safe.
class SippPlanner {
 public:
  explicit SippPlanner(const GridGraph& graph) : graph_(graph) {}

  /// Errors: NotFound (no path under the hard reservations, or the start is reserved at
  /// start_step), ResourceExhausted (max_expansions reached).
  absl::StatusOr<SippResult> Plan(const SippRequest& request, ConstraintTable& table,
                                  DistanceTable& distance_to_goal);

 private:
  struct Node {
    int v;
    int interval;
    int step;
    int conflicts;
    int f;
    int parent;
    bool terminal;
    bool closed;
  };

  static constexpr int kDenseIntervals = 8;  // per vertex; later intervals go to overflow_

  // The best known node of (vertex, interval, terminal), or -1.
  int& BestSlot(int v, int interval, bool terminal);

  const GridGraph& graph_;
  std::vector<Node> nodes_;
  std::vector<int> slot_;
  std::vector<uint32_t> slot_stamp_;
  uint32_t generation_ = 0;
  absl::flat_hash_map<int64_t, int> overflow_;
};

}  // namespace fleetnav::planner
