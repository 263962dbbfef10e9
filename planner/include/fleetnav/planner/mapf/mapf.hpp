#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/planner/grid/grid_graph.hpp"
#include "fleetnav/planner/grid/movingai.hpp"

namespace fleetnav::planner {

/// A multi-agent path finding instance on a GridGraph: agent i starts at vertex starts[i] and
/// must reach goals[i] (Stern et al., SoCS 2019). The graph is referenced, not owned; it must
/// outlive the instance. A value type.
struct MapfInstance {
  const GridGraph* graph = nullptr;
  std::vector<int> starts;
  std::vector<int> goals;

  int num_agents() const { return static_cast<int>(starts.size()); }
  /// InvalidArgument when the sizes differ, a vertex is out of range, two starts or two goals
  /// coincide (the field and agents are named), or a goal is unreachable from its start.
  absl::Status Validate() const;
};

/// A plan: paths[i][t] is the vertex of agent i at step t, from t = 0. After its last entry an
/// agent stays where it is. A value type.
struct MapfSolution {
  std::vector<std::vector<int>> paths;
};

/// The first `num_agents` entries of a scenario as an instance on `graph`. InvalidArgument
/// (naming the entry) when an entry lies on a blocked cell or there are fewer entries.
absl::StatusOr<MapfInstance> InstanceFromScenario(const GridGraph& graph,
                                                  const std::vector<ScenarioEntry>& entries,
                                                  int num_agents);

/// A random instance: distinct starts and distinct goals drawn uniformly (seeded mt19937_64)
/// from the largest connected component. InvalidArgument when it has fewer than num_agents
/// vertices.
absl::StatusOr<MapfInstance> RandomInstance(const GridGraph& graph, int num_agents, uint64_t seed);

/// Cost of one path: the number of steps until the agent last arrives at `goal` (0 when it
/// never leaves it).
int PathCost(const std::vector<int>& path, int goal);
/// Sum of PathCost over the agents.
int64_t SumOfCosts(const MapfInstance& instance, const MapfSolution& solution);
/// Longest PathCost.
int Makespan(const MapfInstance& instance, const MapfSolution& solution);
/// Sum over the agents of the shortest start-goal distance, ignoring the other agents.
int64_t SumOfCostsLowerBound(const MapfInstance& instance);

/// Checks a solution: one path per agent, each starting at its start and ending at its goal,
/// every step a wait or a move to a 4-connected neighbour, no two agents at one vertex at one
/// step (vertex conflict) and no two agents swapping along one edge (edge conflict). The error
/// (InvalidArgument) names the agents, the step and the vertex.
absl::Status ValidateSolution(const MapfInstance& instance, const MapfSolution& solution);

/// The `--paths-out` text: one line per agent, `<index>: x,y x,y ...`.
std::string FormatPaths(const GridGraph& graph, const MapfSolution& solution);

}  // namespace fleetnav::planner

namespace fleetnav::planner {

/// What a multi-agent solver returns: a validated-by-construction plan and its timing.
/// `first_solution_ms` is when the first plan was found, `final_ms` when the returned (best)
/// plan was found. `proven_optimal` is set when an anytime search exhausted its open list.
struct MapfResult {
  MapfSolution solution;
  double first_solution_ms = 0.0;
  double final_ms = 0.0;
  bool proven_optimal = false;
  int64_t expanded_nodes = 0;
  int64_t refine_iterations = 0;  ///< LNS iterations run (accepted or not)
  int64_t refine_accepted = 0;    ///< of which improved the plan
  std::string solver;             ///< "lacam", "eecbs", ...
  /// The goal each agent was planned to: the requested one, or a waiting spot next to it when
  /// another agent was given that goal (MapfPlannerParams::duplicate_goals).
  std::vector<int> planned_goals;
};

}  // namespace fleetnav::planner
