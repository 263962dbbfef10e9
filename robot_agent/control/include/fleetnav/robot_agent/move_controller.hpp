#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/robot_agent/holonomic_tracker.hpp"
#include "fleetnav/robot_agent/motion_controller.hpp"

namespace fleetnav::agent {

struct MoveParams {
  /// End-point augmentation (KUKA thesis ch. 9): a move that turns the direction of travel
  /// back by more than `augment_max_turn_rad` starts along the last direction and bends round
  /// through a knot `augment_radius_m` out, instead of reversing on the spot.
  bool augment_endpoints = true;
  double augment_radius_m = 0.08;
  double augment_max_turn_rad = M_PI / 2;
  double sample_spacing_m = 0.02;
  /// Moves end at rest within 2 mm and 0.01 rad of their end point (the thesis's scans need
  /// millimetres); the carrot is a few centimetres ahead, so the tracker follows the augmented
  /// bend (a few decimetres of path) instead of cutting across it.
  HolonomicTrackerParams tracker = PreciseTracker();
  static HolonomicTrackerParams PreciseTracker() {
    HolonomicTrackerParams p;
    p.goal_tolerance_m = 0.002;
    p.goal_tolerance_rad = 0.01;
    p.carrot_distance_m = 0.05;
    return p;
  }
  absl::Status Validate() const;
};

/// The `move` action on an omnidirectional platform: translate by (dx, dy) in the robot's
/// frame at the start, heading held, tracked holonomically (HolonomicTracker). When the move
/// reverses the direction the platform last travelled in (`entry_direction`, robot frame) and
/// augmentation is on, the path is a cubic spline (KUKA ch. 10) from the start along the old
/// direction through the augmented knot (planner::AugmentEndpoints) to the end point, arriving
/// along the move's own direction: the casters swing round while rolling instead of flipping
/// at a standstill. Without that, the path is the straight line. Not thread-safe.
class MoveController : public MotionController {
 public:
  MoveController(const MoveAction& move, std::optional<Eigen::Vector2d> entry_direction,
                 const RobotModel& model, MoveParams params);
  ControlOutput Step(const ControlInput& input) override;
  /// The path in the map frame (empty before the first Step).
  const std::vector<Pose2>& path() const { return path_; }

 private:
  absl::Status Plan(const Pose2& start);

  MoveAction move_;
  std::optional<Eigen::Vector2d> entry_direction_;
  MoveParams params_;
  HolonomicTracker tracker_;
  std::vector<Pose2> path_;
  double length_m_ = 0.0;
  bool planned_ = false;
};

}  // namespace fleetnav::agent
