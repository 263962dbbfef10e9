#pragma once

#include "absl/status/statusor.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"
#include "fleetnav/planner/trajectory/path_smoothing.hpp"

namespace fleetnav::planner {

/// Parameters of TimePath.
struct PathTimingParams {
  double sample_spacing_m = 0.05;  ///< along straights and arcs, > 0
  double turn_sample_rad = 0.1;    ///< between samples of a turn in place, > 0

  absl::Status Validate() const;
};

/// Times a differential-drive or Ackermann path along its own motion primitives (no smoothing:
/// the lattice and Reeds-Shepp planners already respect these kinematics). Consecutive poses
/// are joined by a straight at constant yaw, a turn in place, or an arc of constant curvature
/// tangent to both poses; the direction of travel is forward or backward along the yaw. The
/// robot stops at every turn in place and at every change of direction. Between stops the
/// classic two-pass velocity profile applies: speed ≤ max_speed_mps (max_reverse_speed_mps
/// backwards), speed × curvature ≤ max_yaw_rate_radps, |acceleration| ≤ max_accel_mps2. Turns
/// in place follow a trapezoidal yaw-rate profile under max_yaw_rate_radps and
/// max_yaw_accel_radps2. InvalidArgument for an omnidirectional model (use SmoothPath), fewer
/// than 2 poses, a backward segment for a model that must not reverse (naming the segment),
/// or bad params.
absl::StatusOr<Trajectory> TimePath(const PathResult& path, const RobotModel& model,
                                    const PathTimingParams& params = {});

/// A timed trajectory for any robot kind: SmoothPath (spline with end-point augmentation) for
/// omnidirectional robots, TimePath for the others.
absl::StatusOr<Trajectory> TrajectoryForPath(const PathResult& path, Costmap* costmap,
                                             const RobotModel& model);

}  // namespace fleetnav::planner
