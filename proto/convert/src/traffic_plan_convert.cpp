#include "fleetnav/proto/traffic_plan_convert.hpp"

#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/geometry_convert.hpp"

namespace fleetnav {

v1::MapInfo ToProto(const MapInfo& info) {
  v1::MapInfo out;
  out.set_map_id(info.map_id);
  out.set_version(info.version);
  out.set_width(static_cast<uint32_t>(info.width));
  out.set_height(static_cast<uint32_t>(info.height));
  out.set_resolution_m(info.resolution_m);
  out.set_description(info.description);
  out.set_created_unix_ms(info.created_unix_ms);
  return out;
}

absl::StatusOr<TrafficAgent> FromProto(const v1::PlanPathsRequest::Agent& agent,
                                       const std::string& field) {
  TrafficAgent out;
  out.robot_id = agent.robot_id();
  out.kind_name = agent.kind_name();
  ASSIGN_OR_RETURN(out.start, FromProto(agent.start(), field + ".start"));
  ASSIGN_OR_RETURN(out.goal, FromProto(agent.goal(), field + ".goal"));
  return out;
}

v1::PlanPathsResponse ToProto(const TrafficPlan& plan, const std::vector<TrafficAgent>& agents) {
  v1::PlanPathsResponse out;
  for (size_t i = 0; i < plan.paths.size(); ++i) {
    v1::PlannedPath* path = out.add_paths();
    if (i < agents.size()) path->set_robot_id(agents[i].robot_id);
    path->set_waits_beside_goal(i < plan.waits_beside_goal.size() && plan.waits_beside_goal[i]);
    for (const PlannedPose& step : plan.paths[i]) {
      v1::TimedPose* wire = path->add_poses();
      wire->set_t_s(step.t_s);
      *wire->mutable_pose() = ToProto(step.pose);
    }
  }
  for (const TrafficDependency& d : plan.dependencies) {
    v1::DependencyEdge* edge = out.add_dependencies();
    edge->set_from_robot_id(d.from_robot_id);
    edge->set_from_action(static_cast<uint32_t>(d.from_action));
    edge->set_to_robot_id(d.to_robot_id);
    edge->set_to_action(static_cast<uint32_t>(d.to_action));
  }
  out.set_sum_of_costs_s(plan.sum_of_costs_s);
  out.set_makespan_s(plan.makespan_s);
  out.set_planning_ms(plan.planning_ms);
  out.set_cell_size_m(plan.cell_size_m);
  out.set_solver(plan.solver);
  return out;
}

}  // namespace fleetnav
