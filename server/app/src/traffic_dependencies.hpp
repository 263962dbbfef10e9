#pragma once

#include <vector>

#include "fleetnav/server/traffic_planner.hpp"

namespace fleetnav::server {

/// Appends the cross-robot edges of a dependency graph to `plan`, with actions numbered per
/// robot. `Graph` has num_actions(), ActionsOf(robot), DependenciesOf(action); `robot_of(id)`
/// gives an action's robot index into `agents`.
template <typename Graph, typename RobotOf>
void AppendDependencies(const Graph& graph, int num_robots, RobotOf robot_of,
                        const std::vector<TrafficAgent>& agents, TrafficPlan* plan) {
  std::vector<int> index_in_robot(graph.num_actions(), 0);
  for (int robot = 0; robot < num_robots; ++robot) {
    const std::vector<int>& mine = graph.ActionsOf(robot);
    for (size_t k = 0; k < mine.size(); ++k) index_in_robot[mine[k]] = static_cast<int>(k);
  }
  for (int id = 0; id < graph.num_actions(); ++id) {
    for (int before : graph.DependenciesOf(id)) {
      const int from = robot_of(before), to = robot_of(id);
      if (from == to) continue;
      plan->dependencies.push_back(
          {agents[from].robot_id, index_in_robot[before], agents[to].robot_id, index_in_robot[id]});
    }
  }
}

}  // namespace fleetnav::server
