#pragma once

#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/robot_agent/path_tracker.hpp"

namespace fleetnav::agent {

struct AckermannPurePursuitParams {
  double desired_speed_mps = 0.5;
  /// Lookahead = |speed| × lookahead_time_s, clamped to [min, max].
  double lookahead_time_s = 1.0;
  double min_lookahead_m = 0.3;
  double max_lookahead_m = 1.5;
  /// Braking (to cusps and the goal) uses this share of the acceleration limit.
  double brake_share = 0.7;
  /// A cusp or the goal counts as reached within this distance, or once passed.
  double goal_tolerance_m = 0.05;
  absl::Status Validate() const;
};

/// Pure pursuit for car-like robots (Coulter, "Implementation of the Pure Pursuit Path
/// Tracking Algorithm", CMU-RI-TR-92-01) on paths with cusps, as the lattice planner gives
/// them for Ackermann models: the path is split where the direction of travel changes; each
/// piece is driven forwards or backwards to its end with the curvature κ = 2y / d² to a
/// lookahead point (the piece extended straight beyond its end, so the robot drives onto it),
/// κ bounded by the steering lock (tan δ_max / wheelbase), the speed bounded by the yaw-rate
/// limit on that curvature and by the braking distance to the piece's end; the robot stops at
/// each cusp before it reverses. Never turns in place; the goal's yaw is what the planned
/// path arrives with. Twist2{v, 0, v κ}, which the drive turns into a steering angle.
class AckermannPurePursuit : public PathTracker {
 public:
  AckermannPurePursuit(AckermannPurePursuitParams params, const RobotModel& model);

  void SetPath(std::vector<Pose2> path) override;
  Twist2 Step(const Pose2& pose_in_map, double dt_s) override;
  bool done() const override { return done_; }
  double remaining_m() const override { return remaining_m_; }
  double cross_track_m() const override { return cross_track_m_; }

 private:
  AckermannPurePursuitParams params_;
  MotionLimits limits_;
  double max_curvature_per_m_ = 0.0;
  std::vector<Pose2> path_;
  std::vector<double> to_goal_m_;
  /// Pieces of one direction: [begin, end] index ranges and their sign (+1 forwards).
  std::vector<std::pair<size_t, size_t>> pieces_;
  std::vector<int> piece_sign_;
  size_t piece_ = 0;
  size_t closest_ = 0;
  double last_speed_mps_ = 0.0;
  double remaining_m_ = 0.0;
  double cross_track_m_ = 0.0;
  bool done_ = false;
};

}  // namespace fleetnav::agent
