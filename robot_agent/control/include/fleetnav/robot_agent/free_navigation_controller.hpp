#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/planner/costmap.hpp"
#include "fleetnav/planner/single_robot_planner.hpp"
#include "fleetnav/robot_agent/motion_controller.hpp"
#include "fleetnav/robot_agent/regulated_pure_pursuit.hpp"

namespace fleetnav::agent {

struct FreeNavigationParams {
  RegulatedPurePursuitParams tracker;
  planner::LatticeParams lattice;
  /// Clearance kept around the footprint when planning.
  double padding_m = 0.1;
  double plan_time_limit_s = 2.0;
  /// Replan from where the robot is when it is further than this from its path.
  double replan_cross_track_m = 0.5;
  absl::Status Validate() const;
};

/// Checks that a free-navigation action's goal and waypoints are free for the robot's
/// footprint on the map (InvalidArgument naming the point), before anything moves.
absl::Status CheckFreeNavigation(const FreeNavigationAction& action, const RobotModel& model,
                                 const OccupancyGrid& map, double padding_m);

/// Free navigation (Lely thesis §6.6.5): plan on the map with the lattice planner for the
/// robot's kinematics (no reversing for the Lely) from the estimated pose through the route's
/// waypoints to the goal, and track the path with regulated pure pursuit; replan from where the
/// robot is when it has left the path. A goal the planner cannot reach exactly fails the
/// action with the reason. Not thread-safe.
class FreeNavigationController : public MotionController {
 public:
  FreeNavigationController(const FreeNavigationAction& action, const RobotModel& model,
                           std::shared_ptr<const OccupancyGrid> map, FreeNavigationParams params);
  ControlOutput Step(const ControlInput& input) override;

 private:
  absl::Status Plan(const Pose2& from_in_map);

  FreeNavigationAction action_;
  RobotModel model_;
  std::shared_ptr<const OccupancyGrid> map_;
  FreeNavigationParams params_;
  std::optional<planner::Costmap> costmap_;
  std::unique_ptr<planner::SingleRobotPlanner> planner_;
  RegulatedPurePursuit tracker_;
  size_t next_waypoint_ = 0;
  double planned_length_m_ = 0.0;
  bool planned_ = false;
};

}  // namespace fleetnav::agent
