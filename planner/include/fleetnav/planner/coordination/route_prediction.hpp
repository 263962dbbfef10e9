#pragma once

#include <Eigen/Core>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"

namespace fleetnav::planner {

/// A free-navigation path in the map frame and its length.
struct WaypointPath {
  std::vector<Pose2> poses;  ///< ends with the goal
  double length_m = 0.0;
};

/// Plans from `from` through `waypoints_m` (passed, not stopped at: any heading within 45°
/// of the next point will do) to `goal` with `planner`, whose costmap has the grid frame
/// `map_origin`. A goal the planner reaches only approximately is NotFound naming it.
absl::StatusOr<WaypointPath> PlanThroughWaypoints(
    SingleRobotPlanner& planner, const Pose2& map_origin, const Pose2& from,
    const std::vector<Eigen::Vector2d>& waypoints_m, const Pose2& goal, double time_limit_s,
    const std::vector<std::optional<double>>& waypoint_yaws_rad = {});

/// Where one action of a route is expected to take the robot: poses along it (at most
/// RoutePredictionParams::pose_step_m / yaw_step_rad apart) and its nominal duration.
struct PredictedAction {
  std::vector<Pose2> poses;
  double duration_s = 0.0;
};

struct RoutePredictionParams {
  double pose_step_m = 0.1;
  double yaw_step_rad = 0.15;
  /// A safety net, as the agent's (FreeNavigationParams::plan_time_limit_s): the planner's
  /// expansion budget ends a search first, so the prediction is the path the agent plans
  /// however busy the machine is (a run replays exactly).
  double plan_time_limit_s = 60.0;
  /// A dock leg along a charger stripe that the marker set does not hold drives this far.
  double default_dock_distance_m = 2.0;
  /// A trolley dock: to this far before the trolley's nearer end (about the agent's approach
  /// frame: its standoff plus the robot's front), then under it, at this speed.
  double trolley_approach_m = 1.0;
  double trolley_dock_speed_mps = 0.15;
  /// Raising the lift at the end of a trolley dock, or lowering it to undock (the robot stands
  /// meanwhile).
  double lift_s = 1.0;
};

/// Predicts the poses a route's actions sweep, from `start`, before the robot drives (the
/// server's traffic coordination orders robots by these). Turns turn in place; straights and
/// fence legs keep the heading for their distance (a fence is followed parallel); stripe and
/// dock legs follow the marker set's stripe pieces from the foot point of the pose to the far
/// end in the direction of travel (or for their distance); free navigation is planned with
/// `planner` as the agent plans it, or, with no planner, drawn straight through its points.
/// The prediction is nominal: the robot's estimate and its reactive controllers put it off
/// by up to some decimetres, which the caller covers with a margin. Errors: InvalidArgument for
/// a stripe leg whose stripe the marker set does not hold; a free-navigation leg the planner
/// cannot plan returns its status naming the action index.
absl::StatusOr<std::vector<PredictedAction>> PredictRoute(const Route& route, const Pose2& start,
                                                          const MarkerSet* markers,
                                                          SingleRobotPlanner* planner,
                                                          const Pose2& map_origin,
                                                          const RoutePredictionParams& params = {});

}  // namespace fleetnav::planner
