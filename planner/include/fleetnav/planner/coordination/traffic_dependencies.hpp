#pragma once

#include <vector>

#include "fleetnav/core/traffic_plan.hpp"
#include "fleetnav/planner/coordination/dependency_graph.hpp"

namespace fleetnav::planner {

/// Appends the cross-robot edges of a dependency graph to `plan`, with actions numbered per
/// robot; the graph's robot r is `agents[r]`.
inline void AppendDependencies(const DependencyGraph& graph,
                               const std::vector<TrafficAgent>& agents, TrafficPlan* plan) {
  for (int id = 0; id < graph.num_actions(); ++id) {
    for (int before : graph.CrossDependenciesOf(id)) {
      plan->dependencies.push_back({agents[graph.RobotOf(before)].robot_id,
                                    graph.IndexInRobot(before), agents[graph.RobotOf(id)].robot_id,
                                    graph.IndexInRobot(id)});
    }
  }
}

}  // namespace fleetnav::planner
