#pragma once

#include <algorithm>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/robot_agent/control/trackers/path_tracker.hpp"

namespace fleetnav::agent {

struct RegulatedPurePursuitParams {
  double desired_speed_mps = 0.3;
  /// Lookahead = speed × lookahead_time_s, clamped to [min, max] (adaptive pure pursuit).
  double lookahead_time_s = 1.5;
  double min_lookahead_m = 0.5;
  double max_lookahead_m = 1.5;
  /// Curvature regulation: below this turning radius the speed scales with radius / it.
  double regulated_min_radius_m = 1.0;
  double min_regulated_speed_mps = 0.05;
  /// Approach: within this distance of the goal the speed scales with the distance left.
  double approach_distance_m = 0.8;
  /// Rotate in place (v = 0) while the lookahead point is more than this off the heading.
  double rotate_to_heading_rad = 0.6;
  double heading_gain_radps_per_rad = 1.0;
  /// The goal is reached within these tolerances (the Lely's lattice ends its paths within
  /// 5 cm of the goal's place, DifferentialLatticeParams).
  double goal_tolerance_m = 0.05;
  double goal_tolerance_rad = 0.03;
  absl::Status Validate() const;
};

/// Regulated pure pursuit (Macenski, Singh, Martín, Ginés, "Regulated Pure Pursuit for Robot
/// Path Tracking", Autonomous Robots 2023) for robots that turn in place and never reverse:
/// adaptive lookahead, the speed regulated down on tight curvature and on the approach to the
/// goal, rotation in place when the path turns away from the heading, and a final rotation to
/// the goal's yaw. A planned turn in place sharper than rotate_to_heading_rad is a stop: the
/// lookahead ends there and the robot slows to it and turns where the plan turns. Turns in
/// place (the final one onto the goal's yaw too) go the way the plan turns them. Respects the
/// model's speed, yaw-rate and acceleration limits. Not thread-safe.
class RegulatedPurePursuit : public PathTracker {
 public:
  RegulatedPurePursuit(RegulatedPurePursuitParams params, MotionLimits limits);

  void SetPath(std::vector<Pose2> path) override;
  Twist2 Step(const Pose2& pose_in_map, double dt_s) override;
  bool done() const override { return done_; }
  double remaining_m() const override { return remaining_m_; }
  double cross_track_m() const override { return cross_track_m_; }
  std::span<const Pose2> path_ahead() const override {
    return std::span<const Pose2>(path_).subspan(std::min(closest_, path_.size()));
  }

 private:
  /// The first pose at or after `from` where the path turns in place by more than
  /// rotate_to_heading_rad (the goal when there is none), from the list SetPath made.
  size_t NextSharpTurn(size_t from) const;
  /// Whether the robot is where the turn in place starting at path pose `turn` is turned.
  bool AtTurnPlace(const Pose2& pose, size_t turn) const;

  RegulatedPurePursuitParams params_;
  MotionLimits limits_;
  std::vector<Pose2> path_;
  std::vector<double> to_goal_m_;  ///< along-path distance from each pose to the goal
  size_t closest_ = 0;
  std::vector<size_t> sharp_turns_;  ///< where turns sharper than rotate_to_heading_rad start
  double final_turn_rad_ = 0.0;      ///< the turn in place the path ends with (signed; 0: none)
  double last_speed_mps_ = 0.0;
  double remaining_m_ = 0.0;
  double cross_track_m_ = 0.0;
  bool done_ = false;
};

}  // namespace fleetnav::agent
