#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/robot_agent/control/avoidance/vfh_plus.hpp"
#include "fleetnav/robot_agent/control/common/polar_pose_control.hpp"
#include "fleetnav/robot_agent/control/trackers/path_tracker.hpp"

namespace fleetnav::agent {

inline VfhPlusParams CarVfhParams() {
  VfhPlusParams p;
  p.window_radius_m = 4.0;
  p.blocked_within_m = 3.2;
  p.free_beyond_m = 3.6;
  return p;
}

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
  /// A piece's end passed (behind the car) within this much to the side, with the car within
  /// passed_end_window_m along the piece of its end, is reached too.
  double passed_aside_m = 0.3;
  double passed_end_window_m = 0.5;
  /// Forward pieces steer round the obstacles they are given (FreeNavigationController gives
  /// those the map does not show) with VFH+, its robot radius and turning radius taken from the
  /// model.
  bool avoid_obstacles = true;
  /// VFH+ for a car at walking pace: it looks 4 m round and blocks what is within 3.2 m, so
  /// that a car with a 1.1 m turning radius can still swerve; it aims at the path point this far
  /// ahead (beyond the pure-pursuit lookahead, so the way through a gap is the target).
  VfhPlusParams vfh = CarVfhParams();
  double vfh_target_distance_m = 3.0;
  /// Within this distance of the goal, at the end of the path, the polar move-to-pose law
  /// drives instead, where the car can follow it (the goal within 45° of its direction of
  /// travel, the law's curvature within the lock); VFH+ rests there (the planned approach is
  /// checked against the map).
  double polar_radius_m = 1.0;
  PolarPoseGains polar;
  /// Slowing in tight places (SetClearances): where the body's clearance on the path from
  /// here to brake_lookahead_m ahead is below slow_clearance_m, the speed is cut in proportion,
  /// to slowest_share of the desired speed at tight_clearance_m and below, so that a gap with
  /// 0.3 m a side is passed at walking pace and the car's tracking error stays small.
  double slow_clearance_m = 0.6;
  double tight_clearance_m = 0.2;
  double slowest_share = 0.35;
  double brake_lookahead_m = 3.0;
  absl::Status Validate() const;
};

/// Pure pursuit for car-like robots (Coulter, "Implementation of the Pure Pursuit Path
/// Tracking Algorithm", CMU-RI-TR-92-01) on paths with cusps, as the lattice planner gives
/// them for Ackermann models: the path is split where the direction of travel changes; each
/// piece is driven forwards or backwards to its end with the curvature κ = 2y / d² to a
/// lookahead point (the piece extended straight beyond its end, so the robot drives onto it),
/// κ bounded by the steering lock (tan δ_max / wheelbase), the speed bounded by the yaw-rate
/// limit on that curvature and by the braking distance to the piece's end; the robot stops at
/// each cusp before it reverses. Where the next metres of a forward piece run into one of the
/// obstacles it is given (what the laser sees and the map does not show), it reports
/// path_obstructed() and steers with VFH+ (Ashesi capstone) towards the path point
/// vfh_target_distance_m ahead, slowing with the clearance, until its caller has replanned; with
/// every direction blocked it brakes to a stop and reports blocked(). The last metre to the goal is
/// driven with the polar move-to-pose law where the car can follow it. Given the body's
/// clearance along the path (SetClearances), it slows where the path runs tight (regulated
/// pure pursuit's proximity heuristic, Macenski et al. 2023). Never turns in place.
/// Twist2{v, 0, v κ}, which the drive turns into a steering angle.
class AckermannPurePursuit : public PathTracker {
 public:
  AckermannPurePursuit(AckermannPurePursuitParams params, const RobotModel& model);

  void SetPath(std::vector<Pose2> path) override;
  Twist2 Step(const Pose2& pose_in_map, double dt_s) override;
  bool done() const override { return done_; }
  double remaining_m() const override { return remaining_m_; }
  double cross_track_m() const override { return cross_track_m_; }
  std::span<const Pose2> path_ahead() const override {
    return std::span<const Pose2>(path_).subspan(std::min(closest_, path_.size()));
  }
  void SetObstacles(std::vector<Eigen::Vector2d> points_in_base) override {
    obstacles_ = std::move(points_in_base);
  }
  /// The body's clearance at each pose of the path last set (metres; the planner's costmap),
  /// for slowing in tight places; empty (the default after SetPath): no slowing.
  void SetClearances(std::vector<double> clearance_m) { clearance_m_ = std::move(clearance_m); }
  bool blocked() const override { return blocked_; }
  bool path_obstructed() const override { return path_obstructed_; }

 private:
  /// Brakes towards standing still at the acceleration limit.
  Twist2 Brake(double dt_s);
  /// The current piece's next vfh_target_distance_m, with the footprint widened by VFH+'s
  /// safety distance, meets one of the obstacles.
  bool PathAheadObstructed(const Pose2& pose) const;
  /// The first pose of the current piece, from the closest one on, at least `distance_m` from
  /// the robot; nullopt when the piece ends nearer.
  std::optional<size_t> FirstPoseAtLeast(const Pose2& pose, double distance_m) const;
  /// The share of the desired speed the clearances from the closest pose to
  /// brake_lookahead_m ahead allow (1 without clearances).
  double ClearanceSpeedShare() const;

  AckermannPurePursuitParams params_;
  MotionLimits limits_;
  Eigen::AlignedBox2d footprint_;  ///< in base_link
  double max_curvature_per_m_ = 0.0;
  std::optional<VfhPlus> vfh_;
  std::vector<Eigen::Vector2d> obstacles_;
  bool blocked_ = false;
  bool path_obstructed_ = false;

  std::vector<Pose2> path_;
  std::vector<double> to_goal_m_;
  std::vector<double> clearance_m_;  ///< per path pose, or empty
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
