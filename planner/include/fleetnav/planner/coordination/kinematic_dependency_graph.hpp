#pragma once

#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/planner/coordination/dependency_graph.hpp"
#include "fleetnav/planner/kinematic/kinematic_mapf.hpp"

namespace fleetnav::planner {

/// One action of one robot in a kinematic plan: from state `from` to the next state `to` (a
/// move or a quarter turn), planned to end at step `planned_step`. Waits are not actions.
struct KinematicAction {
  int robot = 0;
  GridState from;
  GridState to;
  int planned_step = 0;
};

/// The action dependency graph (Hönig, Kiesel, Tinka, Durham and Ayanian, RA-L 2019) of a
/// kinematic plan, with cells instead of vertices so that footprints of any shape are kept
/// apart. Each robot's actions run in order (type 1). For every cell, the robots covering it
/// in the plan are ordered by when they first cover it; a robot's action that starts covering
/// the cell depends on the action with which the previous robot stopped covering it (type 2).
/// A robot that starts an action only when its dependencies are finished, and covers both
/// footprints while the action runs, never overlaps another robot and never deadlocks, whatever
/// the delays: every dependency points forward in planned time, so there are no cycles.
/// Immutable; thread-compatible.
class KinematicDependencyGraph {
 public:
  /// InvalidArgument when the plan does not pass ValidateKinematicPlan.
  static absl::StatusOr<KinematicDependencyGraph> Compile(const KinematicMapfProblem& problem,
                                                          const KinematicMapfPlan& plan);

  /// Robots are the problem's robots; action ids index action().
  const DependencyGraph& graph() const { return graph_; }
  const KinematicAction& action(int id) const { return actions_[id]; }

 private:
  DependencyGraph graph_;
  std::vector<KinematicAction> actions_;
};

}  // namespace fleetnav::planner
