#pragma once

#include <vector>

#include "fleetnav/planner/coordination/dependency_graph.hpp"
#include "fleetnav/server/traffic_planner.hpp"

namespace fleetnav::server {

/// Appends the cross-robot edges of a dependency graph to `plan`, with actions numbered per
/// robot; the graph's robot r is `agents[r]`.
inline void AppendDependencies(const planner::DependencyGraph& graph,
                               const std::vector<TrafficAgent>& agents, TrafficPlan* plan) {
  for (int id = 0; id < graph.num_actions(); ++id) {
    for (int before : graph.CrossDependenciesOf(id)) {
      plan->dependencies.push_back({agents[graph.RobotOf(before)].robot_id,
                                    graph.IndexInRobot(before), agents[graph.RobotOf(id)].robot_id,
                                    graph.IndexInRobot(id)});
    }
  }
}

}  // namespace fleetnav::server
