#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/robot_agent/control/common/motion_controller.hpp"
#include "fleetnav/robot_agent/control/trackers/holonomic_tracker.hpp"
#include "fleetnav/robot_agent/laser_filters.hpp"
#include "fleetnav/robot_agent/trolley_recognition.hpp"

namespace fleetnav::agent {

struct MoveParams {
  /// End-point augmentation (KUKA thesis ch. 9): a move that turns the direction of travel
  /// back by more than `augment_max_turn_rad` starts along the last direction and bends round
  /// through a knot `augment_radius_m` out, instead of reversing on the spot.
  bool augment_endpoints = true;
  double augment_radius_m = 0.08;
  double augment_max_turn_rad = kPi / 2;
  double sample_spacing_m = 0.02;
  /// Moves end at rest within 2 mm and 0.01 rad of their end point (the thesis's scans need
  /// millimetres); the carrot is a few centimetres ahead, so the tracker follows the augmented
  /// bend (a few decimetres of path) instead of cutting across it.
  HolonomicTrackerParams tracker = PreciseTracker();
  /// Leaving from under a trolley just set down: the gate between two legs is used when its
  /// middle lies within this of the move's line and its normal within this angle of the move;
  /// the legs are found in the temporal median of `gate_scans` scans (the docking's filter),
  /// waited for at most `gate_wait_s`.
  double gate_max_offset_m = 0.2;
  double gate_max_angle_rad = 20.0 * kPi / 180.0;
  int gate_scans = 3;
  double gate_wait_s = 1.0;
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
/// at a standstill. Without that, the path is the straight line. A move that starts under a
/// trolley just set down (`leaving_trolley`) leaves through the middle of the two legs ahead,
/// as the laser sees them (FindLegGate), square to them: the set-down trolley can stand a few
/// centimetres and degrees off where the lift held it, and a straight line by the robot's own
/// heading brushed a leg (0.09 m a side). Not thread-safe.
class MoveController : public MotionController {
 public:
  MoveController(const MoveAction& move, std::optional<Eigen::Vector2d> entry_direction,
                 const RobotModel& model, MoveParams params,
                 std::optional<TrolleySpec> leaving_trolley = std::nullopt);
  ControlOutput Step(const ControlInput& input) override;
  /// The path in the map frame (empty before the first Step).
  const std::vector<Pose2>& path() const { return path_; }

 private:
  absl::Status Plan(const Pose2& start, const std::optional<LegGate>& gate);
  /// The gate to leave by, from the perceived legs (nullopt: none found, or not under a trolley).
  std::optional<LegGate> Gate(const Pose2& laser_in_base) const;

  MoveAction move_;
  std::optional<Eigen::Vector2d> entry_direction_;
  MoveParams params_;
  HolonomicTracker tracker_;
  std::vector<Pose2> path_;
  double length_m_ = 0.0;
  double progress_fraction_ = 0.0;
  bool planned_ = false;
  std::optional<TrolleySpec> leaving_trolley_;
  double waited_s_ = 0.0;
  TemporalMedianFilter median_;
  int scans_ = 0;
  std::optional<LaserScanSample> filtered_scan_;
};

}  // namespace fleetnav::agent
