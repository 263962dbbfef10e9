#pragma once

#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/planner/coordination/dependency_graph.hpp"
#include "fleetnav/planner/mapf/mapf.hpp"

namespace fleetnav::planner {

/// One move of one robot: from vertex `from` to the adjacent vertex `to`, planned to arrive at
/// step `planned_step`. Waits are not actions.
struct AdgAction {
  int agent = 0;
  int from = 0;
  int to = 0;
  int planned_step = 0;
};

/// An action dependency graph (Hönig, Kiesel, Tinka, Durham and Ayanian, "Persistent and
/// Robust Execution of MAPF Schedules in Warehouses", RA-L 2019): a plan compiled into each
/// robot's sequence of moves plus cross-robot dependencies. Action b depends on action a when
/// (type 1) a is the previous move of the same robot, or (type 2) b enters a vertex that
/// another robot visited earlier in the plan and a is that robot's move out of it. A robot that
/// starts an action only when all its dependencies are finished, while occupying both ends of a
/// move until it ends, never shares a vertex with another robot and never deadlocks, whatever
/// the delays. Compile refuses plans with rotations (robots that follow each other around a
/// cycle in one step), whose dependencies would be cyclic. Immutable; thread-compatible.
class ActionDependencyGraph {
 public:
  /// Errors: InvalidArgument when the plan does not validate (ValidateSolution);
  /// FailedPrecondition naming the agents when the plan contains a rotation.
  static absl::StatusOr<ActionDependencyGraph> Compile(const MapfInstance& instance,
                                                       const MapfSolution& solution);

  /// Robots are the instance's agents; action ids index action().
  const DependencyGraph& graph() const { return graph_; }
  const AdgAction& action(int id) const { return actions_[id]; }

 private:
  DependencyGraph graph_;
  std::vector<AdgAction> actions_;
};

}  // namespace fleetnav::planner
