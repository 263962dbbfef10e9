#pragma once

#include <memory>
#include <stop_token>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/planner/grid/body_clearance.hpp"
#include "fleetnav/planner/grid/costmap.hpp"

namespace fleetnav::planner {

/// A single-robot path request. Poses are in the costmap's grid frame (metres from the lower-
/// left corner of the grid, yaw relative to the grid).
struct PathRequest {
  Pose2 start;
  Pose2 goal;
  double goal_tolerance_m = 0.15;  ///< > 0
  double goal_tolerance_rad =
      0.25;                   ///< > 0; below half a heading bin only turn-in-place robots reach it
  double time_limit_s = 1.0;  ///< > 0

  absl::Status Validate() const;
};

/// A planned path: poses from the start to the goal. Consecutive poses are joined by the
/// planner's motion primitive (a straight line at constant yaw, a turn in place, a
/// constant-curvature arc forward or in reverse, or — omnidirectional OMPL — a straight line with
/// the yaw interpolated along it). `exact` is false for an approximate result: the path ends at
/// the reachable pose closest to the goal. `expanded` counts search nodes (lattice) or tree
/// states (OMPL).
struct PathResult {
  std::vector<Pose2> poses;
  bool exact = true;
  double length_m = 0.0;
  int64_t expanded = 0;
};

/// The interface of every single-robot planner: plan(request, stop token) → a path or a
/// status. Errors: InvalidArgument (bad request, or start in collision), NotFound (no path and
/// approximate results disabled), DeadlineExceeded, Cancelled.
class SingleRobotPlanner {
 public:
  virtual ~SingleRobotPlanner() = default;
  virtual absl::StatusOr<PathResult> Plan(const PathRequest& request,
                                          std::stop_token stop = {}) = 0;
};

/// Parameters of LatticePlanner.
struct LatticeParams {
  int heading_bins = 16;             ///< yaw discretisation of the search, ≥ 4
  double step_m = 0.0;               ///< primitive length; 0: 1.5 cells (arcs: one bin of turn)
  double turn_cost_m_per_rad = 0.3;  ///< cost of turning in place
  double reverse_cost_factor = 2.0;  ///< cost multiplier of reversing (Ackermann), ≥ 1
  /// Cost of a cusp, a switch between driving forward and reversing, in metres of path
  /// (Dolgov et al. 2010 penalize direction switches). ≥ 0.
  double direction_switch_cost_m = 0.0;
  double heuristic_weight = 1.5;   ///< weighted A*, ≥ 1 (bounded suboptimal)
  bool allow_approximate = true;   ///< return the closest reachable pose when no path exists
  int max_expansions = 4'000'000;  ///< > 0
  /// Cost of nearing obstacles: each metre of a primitive costs 1 + clearance_weight ×
  /// ((preferred_clearance_m − c) / preferred_clearance_m)² where the body's clearance c is
  /// below preferred_clearance_m, so a path keeps to the middle of a gap and passes it along
  /// its axis. 0 (the default): length alone. ≥ 0.
  double clearance_weight = 0.0;
  double preferred_clearance_m = 0.5;  ///< > 0
  /// Coastal navigation (Roy, Burgard, Fox and Thrun, "Coastal Navigation — Mobile Robot
  /// Navigation with Uncertainty in Dynamic Environments", ICRA 1999): where base_link is
  /// farther than coast_reach_m from every obstacle, out of the reach of short-range sensors
  /// and localized by dead reckoning alone, each metre of a primitive costs up to
  /// coastal_weight more (rising over the first metre past the reach), so a long way over open
  /// floor keeps a wall or a fence within the sensors' reach where that costs little extra
  /// length. 0 (the default): off. ≥ 0.
  double coastal_weight = 0.0;
  double coast_reach_m = 2.5;  ///< > 0
  /// A robot that turns in place can end on its goal's place closely: the search looks for an
  /// end within this of the goal's place, for up to 1 m of cost more than the first end within
  /// the request's goal_tolerance_m, which it takes when it finds none (on a coarse map there
  /// may be none). 0 (the default): the request's tolerance alone. ≥ 0.
  double goal_place_tolerance_m = 0.0;
  /// Ackermann models: every analytic_every-th expansion within analytic_range_m of the goal,
  /// try the shortest Reeds-Shepp curve (Dubins without reversing) to the goal itself and end
  /// the search with it when it is free and keeps analytic_min_clearance_m (or as much as the
  /// start of the curve and the goal have, where they have less). 0: never (the goal is then
  /// reached within the request's tolerances only).
  int analytic_every = 0;
  /// Ackermann arcs (and shots) at this many times the minimum turning radius, ≥ 1: a path at
  /// full lock leaves the tracker no steering to correct with, and the car drifts outside the
  /// curve.
  double turning_radius_factor = 1.0;
  /// A start in collision that is only touching (BodyClearance above -0.25 m, which a body
  /// touching head-on measures, or within the padding): the search first backs out of it, every
  /// primitive gaining body clearance, for at most this far (then as usual), instead of refusing
  /// the start — a robot that has touched a box backs off the way it can and goes on. 0: refused. ≥
  /// 0.
  double escape_m = 0.0;
  double analytic_range_m = 8.0;          ///< > 0
  double analytic_min_clearance_m = 0.3;  ///< ≥ 0

  absl::Status Validate() const;
};

/// The lattice for omnidirectional platforms in stores: clearance-weighted costs, so that a
/// path rounds the end of a shelf row and passes trolleys with room to spare where there is room;
/// no coastal costs (a laser sees the store); backing out of a touch, and the same expansion
/// budget as the cars'.
LatticeParams PlatformLatticeParams();

/// The lattice for robots that turn in place and must not reverse (the Lely feeder in barns):
/// clearance-weighted costs, so that a 2.3 m body turns in place where it has room — the goal's
/// tolerance or a lane's width away from a fence — not at the edge of what the padding allows;
/// coastal costs beyond its side ultrasonics' 2.5 m, so that a way across the barn follows a
/// fence or a wall the localization can see rather than dead-reckoning over open floor; plain
/// A* (heuristic weight 1); the goal's place within 5 cm (the tracker ends within as much); no
/// escape (backing out of a touch needs reversing); the same expansion budget.
LatticeParams DifferentialLatticeParams();

/// The lattice for car-like robots in tight places (box fields, gates): clearance-weighted
/// costs, analytic Reeds-Shepp expansion to the exact goal pose, 32 heading bins, and arcs
/// 1.3 times the minimum turning radius, a cusp costing 3 m of path (a car that reversed just
/// before a gap entered it off its axis), backing out of a touch (escape_m 1 m), and an
/// expansion budget of 3 M that ends a fruitless search before any wall-time limit does.
LatticeParams CarLatticeParams();

/// A hybrid-A* lattice planner of our own (Dolgov, Thrun, Montemerlo and Diebel, "Path
/// Planning for Autonomous Vehicles in Unknown Semi-structured Environments", IJRR 2010:
/// continuous poses, closed set on (cell, heading bin), obstacle-aware 2D Dijkstra heuristic)
/// with motion primitives per kinematics: differential drive moves straight forward and turns
/// in place, never reversing when the model's max_reverse_speed_mps is 0 (the Lely robot);
/// omnidirectional moves in 8 directions at any yaw and turns in place; Ackermann drives arcs of
/// the minimum turning radius wheelbase / tan(max_steering) and straights, forward and (if the
/// model allows) backward. Turns in place end on heading bins' centres, the first one from any
/// start yaw, so every search can line up with the map's axes. Every primitive is checked against
/// the costmap's footprint test every half cell. With LatticeParams::clearance_weight its cost
/// grows as the body nears obstacles, and with analytic_every an Ackermann search ends on the
/// shortest Reeds-Shepp curve to the exact goal (Dolgov et al.'s analytic expansion). Holds a
/// pointer to the costmap, which must outlive it. Not thread-safe.
class LatticePlanner : public SingleRobotPlanner {
 public:
  LatticePlanner(Costmap* costmap, const RobotModel& model, const LatticeParams& params);
  absl::StatusOr<PathResult> Plan(const PathRequest& request, std::stop_token stop = {}) override;
  double turning_radius_m() const { return turning_radius_m_; }

 private:
  struct Primitive {
    double forward_m;  // signed arc length along the heading (0 for turns in place)
    double lateral_m;  // omni sideways component in the robot frame
    double dyaw_rad;
    double cost;
  };
  bool SegmentFree(const Pose2& from, const Primitive& p) const;
  static Pose2 Apply(const Pose2& from, const Primitive& p, double fraction);
  /// The cost multiplier of a body clearance (LatticeParams::clearance_weight).
  double ClearanceFactor(double clearance_m) const;
  /// A turn in place from `yaw_rad` turns onto the next heading bin's centre that way (a whole
  /// bin from a centre), so that a search from any start yaw reaches the yaws of the map's axes:
  /// a platform carrying a trolley fits a shelf aisle beside another trolley at 0° and not 6°
  /// off it, where a start yaw plus whole bins had left it. Moves are returned as they are.
  Primitive OntoHeadingBins(double yaw_rad, const Primitive& p) const;
  /// The extra cost per metre with base_link this far from the nearest obstacle
  /// (LatticeParams::coastal_weight).
  double CoastExtra(double obstacle_distance_m) const;
  /// The analytic expansion from `from` to `goal` (poses after `from`, the goal last), or
  /// empty when the curve collides or passes closer to obstacles than allowed.
  std::vector<Pose2> AnalyticShot(const Pose2& from, const Pose2& goal);

  Costmap* costmap_;
  RobotModel model_;
  LatticeParams params_;
  double turning_radius_m_ = 0.0;
  std::vector<Primitive> primitives_;
  std::shared_ptr<const BodyClearance> clearance_;  ///< with clearance costs or shots
  double base_room_m_ = 0.0;  ///< the largest disc round base_link inside the footprint
};

/// The lattice planner for a robot model (every kinematics kind); InvalidArgument for bad
/// params or model. planner_factory.hpp chooses between the lattice and the OMPL planners.
absl::StatusOr<std::unique_ptr<SingleRobotPlanner>> MakeSingleRobotPlanner(
    Costmap* costmap, const RobotModel& model, const LatticeParams& params);

}  // namespace fleetnav::planner
