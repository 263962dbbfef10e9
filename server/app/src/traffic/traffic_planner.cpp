#include "fleetnav/server/traffic/traffic_planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <set>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/core/zone.hpp"
#include "fleetnav/planner/coordination/action_dependency_graph.hpp"
#include "fleetnav/planner/coordination/kinematic_traffic.hpp"
#include "fleetnav/planner/coordination/traffic_dependencies.hpp"
#include "fleetnav/planner/grid/coarse_grid.hpp"
#include "fleetnav/planner/mapf/mapf_planner.hpp"

namespace fleetnav::server {

absl::StatusOr<TrafficPlan> TrafficPlanner::Plan(const std::string& map_id, uint32_t map_version,
                                                 const std::vector<TrafficAgent>& agents,
                                                 double time_limit_s) {
  const auto started = std::chrono::steady_clock::now();
  if (agents.empty()) return absl::InvalidArgumentError("agents: empty");
  if (!(time_limit_s > 0.0 && time_limit_s <= 60.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("time_limit_s: must be in (0, 60], got ", time_limit_s));
  }
  double cell_m = 0.0, speed_mps = 1e9;
  std::set<std::string> ids;
  std::vector<RobotModel> models;
  for (size_t i = 0; i < agents.size(); ++i) {
    const std::string field = absl::StrCat("agents[", i, "]");
    absl::StatusOr<RobotModel> model = RobotModelByKind(agents[i].kind_name);
    if (!model.ok()) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".kind_name: unknown kind '", EchoInput(agents[i].kind_name), "'"));
    }
    if (!ids.insert(agents[i].robot_id).second || agents[i].robot_id.empty()) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".robot_id: empty or repeated"));
    }
    if (!agents[i].start.IsFinite() || !agents[i].goal.IsFinite()) {
      return absl::InvalidArgumentError(absl::StrCat(field, ": start and goal must be finite"));
    }
    cell_m = std::max(cell_m, 2.0 * model->CircumscribedRadius());
    speed_mps = std::min(speed_mps, model->limits.max_speed_mps);
    models.push_back(*std::move(model));
  }
  ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredMap> shared,
                   site_data_->Map(map_id, map_version));
  const storage::StoredMap& stored = *shared;
  // The agents plan round the no-go zones: so do the plans.
  const std::shared_ptr<const storage::StoredZoneSet> zones =
      zones_ != nullptr ? zones_->Latest(map_id) : nullptr;
  std::optional<OccupancyGrid> with_zones;
  const OccupancyGrid& grid =
      PlanningGrid(stored.grid, zones != nullptr ? &zones->zones : nullptr, with_zones);
  auto elapsed_ms = [&] {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started)
        .count();
  };
  // Robots whose heading matters (the Lely must not reverse) are planned with headings and
  // footprints first; when that does not fit or finish, as points on one coarse grid.
  std::string kinematic_failure;
  if (planner::UseKinematicTraffic(models)) {
    absl::StatusOr<TrafficPlan> plan =
        planner::PlanKinematicTraffic(grid, agents, models, 0.5 * time_limit_s);
    if (plan.ok()) {
      plan->planning_ms = elapsed_ms();
      return plan;
    }
    kinematic_failure = std::string(plan.status().message());
    time_limit_s = std::max(time_limit_s - elapsed_ms() / 1000.0, 0.1 * time_limit_s);
  }
  const planner::CoarseGrid coarse = planner::Coarsen(grid, cell_m);
  const planner::GridGraph graph(coarse.map);

  // Snap each start and goal to its coarse cell (in the map's own frame).
  auto vertex_of = [&](const Pose2& pose, const std::string& field) -> absl::StatusOr<int> {
    int x = 0, y = 0;
    coarse.CellOf(pose, &x, &y);
    const int v = graph.VertexAt(x, y);
    if (v == planner::GridGraph::kNone) {
      return absl::InvalidArgumentError(absl::StrCat(field, ": not on a free planning cell (",
                                                     coarse.cell_m, " m cells of the map)"));
    }
    return v;
  };
  planner::MapfInstance instance;
  instance.graph = &graph;
  for (size_t i = 0; i < agents.size(); ++i) {
    const std::string field = absl::StrCat("agents[", i, "]");
    ASSIGN_OR_RETURN(int start, vertex_of(agents[i].start, field + ".start"));
    ASSIGN_OR_RETURN(int goal, vertex_of(agents[i].goal, field + ".goal"));
    instance.starts.push_back(start);
    instance.goals.push_back(goal);
  }

  planner::MapfPlannerParams params;
  // Robots execute through an action dependency graph, which needs a plan without rotations.
  params.forbid_rotations = true;
  absl::StatusOr<planner::MapfResult> result =
      planner::MapfPlanner(params).Solve(instance, {time_limit_s});
  if (!result.ok()) return result.status();
  // A robot whose goal another robot keeps was planned to the coarse cell beside it.
  std::vector<bool> at_requested_goal(instance.num_agents());
  for (int i = 0; i < instance.num_agents(); ++i) {
    at_requested_goal[i] = result->planned_goals[i] == instance.goals[i];
  }
  instance.goals = result->planned_goals;
  absl::StatusOr<planner::ActionDependencyGraph> adg =
      planner::ActionDependencyGraph::Compile(instance, result->solution);
  if (!adg.ok()) return adg.status();

  TrafficPlan plan;
  plan.cell_size_m = coarse.cell_m;
  for (bool kept : at_requested_goal) plan.waits_beside_goal.push_back(!kept);
  plan.solver = result->solver;
  if (!kinematic_failure.empty()) plan.solver += " (kinematic: " + kinematic_failure + ")";
  const double step_s = coarse.cell_m / speed_mps;
  for (int i = 0; i < instance.num_agents(); ++i) {
    const std::vector<int>& cells = result->solution.paths[i];
    std::vector<PlannedPose> path;
    double yaw = agents[i].start.yaw_rad();
    for (size_t t = 0; t < cells.size(); ++t) {
      if (t + 1 < cells.size() && cells[t + 1] != cells[t]) {
        yaw = std::atan2(graph.Y(cells[t + 1]) - graph.Y(cells[t]),
                         graph.X(cells[t + 1]) - graph.X(cells[t])) +
              coarse.origin.yaw_rad();
      }
      const Eigen::Vector2d in_map = coarse.CenterOf(graph.X(cells[t]), graph.Y(cells[t]));
      path.push_back({t * step_s, Pose2(in_map.x(), in_map.y(), yaw)});
    }
    path.front().pose = agents[i].start;
    if (at_requested_goal[i]) path.back().pose = agents[i].goal;
    plan.sum_of_costs_s += planner::PathCost(cells, instance.goals[i]) * step_s;
    plan.makespan_s = std::max(plan.makespan_s, path.back().t_s);
    plan.paths.push_back(std::move(path));
  }
  planner::AppendDependencies(adg->graph(), agents, &plan);
  plan.planning_ms = elapsed_ms();
  return plan;
}

}  // namespace fleetnav::server
