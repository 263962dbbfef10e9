#pragma once

#include <string>
#include <vector>

#include "fleetnav/core/pose2.hpp"

namespace fleetnav {

/// One robot of a coordinated plan (PlanPaths): its kind (a RobotModel preset, which sets the
/// cell size, speed and motion) and where it starts and must end.
struct TrafficAgent {
  std::string robot_id;
  std::string kind_name;
  Pose2 start;
  Pose2 goal;
};

/// Where a planned robot is `t_s` seconds after the plan starts.
struct PlannedPose {
  double t_s = 0.0;
  Pose2 pose;
};

/// "Action `to_action` of robot `to` may start only after action `from_action` of robot `from`
/// has finished" (an edge of the action dependency graph).
struct TrafficDependency {
  std::string from_robot_id;
  int from_action = 0;
  std::string to_robot_id;
  int to_action = 0;
};

/// Coordinated paths of several robots on one map, with the dependencies that keep them apart
/// under any delay and the planner's figures.
struct TrafficPlan {
  std::vector<std::vector<PlannedPose>> paths;  ///< per agent, in request order
  std::vector<TrafficDependency> dependencies;
  /// Per agent: another robot kept this agent's goal, so it was planned to the cell beside it.
  std::vector<bool> waits_beside_goal;
  double sum_of_costs_s = 0.0;
  double makespan_s = 0.0;
  double planning_ms = 0.0;
  double cell_size_m = 0.0;
  std::string solver;
};

}  // namespace fleetnav
