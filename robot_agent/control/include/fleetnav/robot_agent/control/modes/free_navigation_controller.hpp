#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"
#include "fleetnav/planner/trajectory/path_smoothing.hpp"
#include "fleetnav/robot_agent/control/avoidance/unmapped_obstacles.hpp"
#include "fleetnav/robot_agent/control/common/motion_controller.hpp"
#include "fleetnav/robot_agent/control/trackers/ackermann_pure_pursuit.hpp"
#include "fleetnav/robot_agent/control/trackers/holonomic_tracker.hpp"
#include "fleetnav/robot_agent/control/trackers/path_tracker.hpp"
#include "fleetnav/robot_agent/control/trackers/regulated_pure_pursuit.hpp"

namespace fleetnav::agent {

struct FreeNavigationParams {
  /// Differential drive.
  RegulatedPurePursuitParams tracker;
  /// Omnidirectional platforms: the path is spline-smoothed, then tracked holonomically.
  HolonomicTrackerParams holonomic;
  planner::SmoothingParams smoothing;
  /// Ackermann robots: tracked with cusps. Every kind plans with
  /// planner::NavigationPlannerParams(model), the planner fleetnavd predicts it with.
  AckermannPurePursuitParams ackermann;
  /// Clearance kept around the footprint when planning.
  double padding_m = 0.1;
  /// A safety net only: the lattices' expansion budgets end a search first, so that the same
  /// run plans the same on an idle and on a busy machine (with 2 s, and then 5 s, a busy
  /// machine turned long ways round a store's shelves into "cannot be reached").
  double plan_time_limit_s = 60.0;
  /// Replan from where the robot is when it is further than this from its path.
  double replan_cross_track_m = 0.5;
  /// When the tracker has ended further than this from the goal pose (a car that reached the
  /// end of its path at the wrong heading), plan again from there, at most
  /// max_goal_corrections times; after that the action ends where the robot is.
  double goal_check_m = 0.15;
  double goal_check_rad = 0.1;
  int max_goal_corrections = 3;
  /// A tracker that finds every direction blocked by what the laser sees (and not on the map)
  /// waits this long for the way to clear, then fails the action with the reason.
  double blocked_timeout_s = 5.0;
  /// What the laser sees that the map does not show: VFH+ steers round it, and an Ackermann
  /// robot that avoids obstacles plans round it.
  UnmappedObstaclesParams unmapped;
  /// A path that runs into an unmapped obstacle is planned again at most this often.
  double obstructed_replan_interval_s = 1.0;
  /// Leaving the path more often than this within replan_window_s (a robot steered round and
  /// round by what is not on the map) fails the action instead of wandering on.
  int max_replans_in_window = 6;
  double replan_window_s = 60.0;
  absl::Status Validate() const;
};

/// Checks that a free-navigation action's goal and waypoints are free for the robot's
/// footprint on the map (InvalidArgument naming the point), before anything moves.
absl::Status CheckFreeNavigation(const FreeNavigationAction& action, const RobotModel& model,
                                 const OccupancyGrid& map, double padding_m);

/// A trolley's outline on the map: its centre and heading (the robot's pose when its lift
/// latched or set down the trolley) and its size (length, width).
struct LoadOutline {
  Pose2 pose_in_map;
  Eigen::Vector2d size_m;
};

/// The trolleys a robot has moved on the map it navigates: where it lifted them off (the map
/// still shows them there) and where it set them down (the map does not show them there).
struct MovedLoads {
  std::vector<LoadOutline> lifted_from;
  std::vector<LoadOutline> set_down_at;

  /// Records a trolley of `size_m` latched at `pose_in_map` (a set-down place there is
  /// forgotten: the trolley has left it again).
  void Lifted(const Pose2& pose_in_map, const Eigen::Vector2d& size_m);
  /// Records a trolley of `size_m` set down at `pose_in_map`.
  void SetDown(const Pose2& pose_in_map, const Eigen::Vector2d& size_m);
};

/// Free navigation (Lely thesis §6.6.5): plan on the map from the estimated pose through the
/// route's waypoints to the goal — the lattice planner of planner::NavigationPlannerParams (no
/// reversing for the Lely; clearance costs for omni platforms and cars, Reeds-Shepp shots onto
/// the goal for cars) — and track the
/// path with the tracker of the robot's drive (which also sees the latest laser scan's returns
/// that the map does not explain, carried along by odometry between scans, and may steer round
/// them): regulated pure pursuit for differential drive;
/// for omnidirectional platforms the path is first smoothed into a cubic spline with end-point
/// augmentation (KUKA thesis ch. 9–10, checked against the costmap) and followed by the
/// HolonomicTracker; Ackermann robots follow it with AckermannPurePursuit, cusps included. Replan
/// from where the robot is when it has left the path — an Ackermann robot that steers round
/// obstacles plans round those its laser has seen too (UnmappedObstacles, marked on a copy of
/// the map), and plans again as soon as the path ahead runs into one. A goal the planner cannot
/// reach exactly fails the action with the reason. A robot that carries a trolley is given as
/// `model` grown to it (RouteContext::NavigationModel) with `carrying`: the map's obstacles
/// under that footprint where the action starts are the carried trolley's own legs as the map
/// remembers them, and are left off the plan. The trolleys the robot moved (`moved`) are where
/// it left them: the map's obstacles within a place one was lifted off are left off the plan,
/// and the outline of each one set down is an obstacle (unless the robot stands under it as it
/// plans: a `move` takes it out first). Not thread-safe.
class FreeNavigationController : public MotionController {
 public:
  FreeNavigationController(const FreeNavigationAction& action, const RobotModel& model,
                           std::shared_ptr<const OccupancyGrid> map, FreeNavigationParams params,
                           bool carrying = false, MovedLoads moved = {});
  ControlOutput Step(const ControlInput& input) override;
  std::optional<double> PathDistanceToGate(const Pose2& gate) const override;

 private:
  absl::Status Plan(const Pose2& from_in_map);
  /// The costmap (the map, plus what the laser sees now when AvoidsUnmappedObstacles) and the
  /// planner on it.
  absl::Status BuildPlanner(const Pose2& from_in_map);
  /// Ackermann robots steer (VFH+) and plan round what the laser sees that the map does not
  /// show; the other drives follow their plans.
  bool AvoidsUnmappedObstacles() const;
  /// The body's clearance at each pose of a path (map frame), from the planning costmap.
  std::vector<double> ClearancesAlong(const std::vector<Pose2>& path_in_map) const;
  /// An omni platform's path (map frame) as a spline with augmented end points.
  std::vector<Pose2> Smoothed(const std::vector<Pose2>& path_in_map);
  /// The latest scan's points, carried to this tick's base_link by odometry, for the tracker.
  void PassObstacles(const ControlInput& input);

  FreeNavigationAction action_;
  RobotModel model_;
  std::shared_ptr<const OccupancyGrid> map_;
  FreeNavigationParams params_;
  std::optional<planner::Costmap> costmap_;
  std::unique_ptr<planner::SingleRobotPlanner> planner_;
  std::unique_ptr<PathTracker> tracker_;
  AckermannPurePursuit* car_tracker_ = nullptr;  ///< tracker_ for Ackermann robots
  size_t next_waypoint_ = 0;
  int goal_corrections_ = 0;
  double planned_length_m_ = 0.0;
  bool planned_ = false;
  /// The latest laser scan's points in base_link that the map does not explain, and the
  /// odometry pose they were seen from.
  std::vector<Eigen::Vector2d> scan_points_in_base_;
  Pose2 scan_pose_in_odom_;
  /// Cells the last BuildPlanner marked occupied from the scans.
  int marked_cells_ = 0;
  UnmappedObstacles unmapped_;
  double blocked_s_ = 0.0;
  /// Time since the action started, and when it last left its path (within the window).
  double elapsed_s_ = 0.0;
  double last_plan_s_ = 0.0;
  std::vector<double> replans_at_s_;
  bool carrying_ = false;
  /// Where the action started, carrying: the map is cleared under the footprint there.
  std::optional<Pose2> carried_from_in_map_;
  MovedLoads moved_;
};

}  // namespace fleetnav::agent
