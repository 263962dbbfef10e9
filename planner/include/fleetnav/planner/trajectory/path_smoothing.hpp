#pragma once

#include <Eigen/Core>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"

namespace fleetnav::planner {

/// Parameters of SmoothPath.
struct SmoothingParams {
  /// Spacing of the output samples along the path; capped at half a costmap cell. > 0.
  double sample_spacing_m = 0.05;
  /// End-point augmentation (AugmentEndpoints): where the path turns back by more than
  /// `augment_max_turn_rad` at a knot, an extra knot `augment_radius_m` beyond it. > 0; (0, pi].
  double augment_radius_m = 0.3;
  double augment_max_turn_rad = kPi / 2;

  absl::Status Validate() const;
};

/// One sample of a smoothed, timed path.
struct TrajectoryPoint {
  double t_s = 0.0;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;      ///< platform yaw (grid frame)
  double heading_rad = 0.0;  ///< direction of travel (grid frame)
  double speed_mps = 0.0;    ///< along the path, ≥ 0
};

/// A smoothed, timed path: samples from the start to the goal.
struct Trajectory {
  std::vector<TrajectoryPoint> points;
  int intervals = 0;      ///< intervals between the path's distinct positions (knots)
  int raw_intervals = 0;  ///< intervals kept as the planner's straight segments
};

/// Turns an omnidirectional robot's path into a C² cubic-spline trajectory (CubicSpline: KUKA
/// thesis ch. 10, chord-length parameters, given end tangents) with end-point augmentation
/// (ch. 9, so that going sideways and back bends round instead of reversing 180° at once) and
/// times it under the model's limits.
///
/// Knots are the path's distinct positions; a turn in place at a knot is spread over the
/// following interval, the platform yaw interpolated along each interval from knot to knot.
/// Fallback rule: the trajectory is sampled at most half a cell apart and every sample is tested
/// with the costmap's footprint test; an interval in which any sample collides is replaced by
/// the planner's own motion (turn in place at its start knot, then the straight segment), and
/// the remaining runs of intervals are refitted with end tangents along the neighbouring
/// straight segments, so the direction of travel stays continuous where the robot moves. This
/// repeats until no sample collides (at worst the planner's path, which it checked itself).
/// The robot stops where a straight segment meets another at an angle and where it turns in
/// place.
///
/// Timing: speed ≤ max_speed_mps; rate of change of the direction of travel (speed ×
/// curvature) and of the platform yaw ≤ max_yaw_rate_radps; |acceleration| along the path ≤
/// max_accel_mps2 (the two-pass profile of TimeParameterize); at rest at both ends; turns in
/// place at max_yaw_rate_radps without a yaw-acceleration ramp. Lateral-speed and
/// yaw-acceleration limits are not applied.
///
/// InvalidArgument for a non-omnidirectional model, an empty path or bad params.
absl::StatusOr<Trajectory> SmoothPath(const PathResult& path, Costmap* costmap,
                                      const RobotModel& model, const SmoothingParams& params);

}  // namespace fleetnav::planner
