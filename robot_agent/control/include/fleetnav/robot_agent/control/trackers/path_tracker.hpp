#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_state.hpp"

namespace fleetnav::agent {

/// Follows a planned path (map frame, ending at the goal pose) to its goal, one control tick at
/// a time, as the robot's kinematics allow: one implementation per drive kind (regulated pure
/// pursuit for differential drive, a holonomic tracker for omni platforms, Ackermann pure
/// pursuit with cusps for car-like robots). Not thread-safe.
class PathTracker {
 public:
  virtual ~PathTracker() = default;
  /// A path in the map frame ending at the goal pose (at least one pose).
  virtual void SetPath(std::vector<Pose2> path) = 0;
  /// The body twist to drive this tick from `pose_in_map`.
  virtual Twist2 Step(const Pose2& pose_in_map, double dt_s) = 0;
  /// The goal pose is reached within the tracker's tolerances.
  virtual bool done() const = 0;
  /// Distance from the robot's closest path point to the goal along the path.
  virtual double remaining_m() const = 0;
  /// Distance from the robot to the closest path point (for replanning).
  virtual double cross_track_m() const = 0;
  /// The path from the robot's closest path pose (as of the last Step) to the goal.
  virtual std::span<const Pose2> path_ahead() const = 0;
  /// What the robot's laser sees this tick, as points in base_link; trackers that avoid
  /// obstacles locally steer round them, the others ignore them.
  virtual void SetObstacles(std::vector<Eigen::Vector2d> /*points_in_base*/) {}
  /// Obstacles block every direction the tracker could drive: it stands still.
  virtual bool blocked() const { return false; }
  /// The path just ahead runs into one of the obstacles: its caller should plan again.
  virtual bool path_obstructed() const { return false; }
};

}  // namespace fleetnav::agent
