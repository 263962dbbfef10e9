#pragma once

#include <algorithm>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/robot_agent/control/trackers/path_tracker.hpp"

namespace fleetnav::agent {

struct HolonomicTrackerParams {
  double desired_speed_mps = 0.3;
  /// The carrot: the path point this far ahead of the closest one (along the path), never
  /// past a turn in place or the goal.
  double carrot_distance_m = 0.3;
  /// Cross-track correction and heading gains (per second).
  double position_gain_per_s = 1.5;
  double heading_gain_per_s = 1.5;
  /// Translation slows to a stop while the platform is this far off the path's yaw.
  double heading_stop_rad = 0.25;
  /// Braking (to turns in place and the goal) uses this share of the acceleration limit.
  double brake_share = 0.7;
  double goal_tolerance_m = 0.05;
  double goal_tolerance_rad = 0.03;
  absl::Status Validate() const;
};

/// Path tracking for omnidirectional (mecanum) platforms (KUKA omniMove thesis, ch. 9):
/// the platform translates in any direction while it turns, so position and yaw are
/// controlled apart. Each tick the velocity in the map frame is the path's tangent times a
/// speed regulated by the braking distance to the next stop (a planned turn in place or the
/// goal), plus a proportional pull towards a carrot a little ahead on the path; the yaw follows
/// the path's yaw where the platform is (the spline-smoothed path of planner::SmoothPath
/// spreads yaw changes over its intervals and checked its sweep with them): the path's turning
/// per metre times the speed, fed forward, plus a proportional correction, the speed lowered
/// so that turning stays within the yaw-rate limit. Turns in place in the path are turned
/// where they were planned. Both are rotated into the body frame and limited to the model's
/// speed, lateral-speed, yaw-rate and acceleration limits (the whole twist scaled down
/// together, so the direction holds).
class HolonomicTracker : public PathTracker {
 public:
  HolonomicTracker(HolonomicTrackerParams params, MotionLimits limits);

  void SetPath(std::vector<Pose2> path) override;
  Twist2 Step(const Pose2& pose_in_map, double dt_s) override;
  bool done() const override { return done_; }
  double remaining_m() const override { return remaining_m_; }
  double cross_track_m() const override { return cross_track_m_; }
  std::span<const Pose2> path_ahead() const override {
    return std::span<const Pose2>(path_).subspan(std::min(closest_, path_.size()));
  }

 private:
  /// The first index after `from` where the path turns in place, or the last index.
  size_t NextStop(size_t from) const;

  HolonomicTrackerParams params_;
  MotionLimits limits_;
  std::vector<Pose2> path_;
  std::vector<double> to_goal_m_;  ///< along-path distance from each pose to the goal
  size_t closest_ = 0;
  Twist2 last_command_;
  double remaining_m_ = 0.0;
  double cross_track_m_ = 0.0;
  bool done_ = false;
};

}  // namespace fleetnav::agent
