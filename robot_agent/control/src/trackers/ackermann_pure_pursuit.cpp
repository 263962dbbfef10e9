#include "fleetnav/robot_agent/control/trackers/ackermann_pure_pursuit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/rate_limit.hpp"
#include "fleetnav/robot_agent/control/common/path_geometry.hpp"

namespace fleetnav::agent {
namespace {

/// Steps shorter than this carry no direction of their own.
constexpr double kTinyStepM = 1e-4;
/// Slowest speed while a piece's end is still ahead, so it is reached in finite time.
constexpr double kCreepSpeedMps = 0.03;
/// Among obstacles the speed falls with VFH+'s clearance along the chosen direction, to this
/// share of the top speed.
constexpr double kVfhSlowestShare = 0.3;
/// The path ahead is checked against the obstacles every this far along it.
constexpr double kObstructionStepM = 0.1;

}  // namespace

absl::Status AckermannPurePursuitParams::Validate() const {
  for (double v :
       {desired_speed_mps, lookahead_time_s, min_lookahead_m, max_lookahead_m, goal_tolerance_m}) {
    if (!(std::isfinite(v) && v > 0.0)) {
      return absl::InvalidArgumentError(
          "Ackermann pure pursuit parameters: must be finite and > 0");
    }
  }
  if (min_lookahead_m > max_lookahead_m) {
    return absl::InvalidArgumentError("min_lookahead_m: must be <= max_lookahead_m");
  }
  if (!(brake_share > 0.0 && brake_share <= 1.0)) {
    return absl::InvalidArgumentError("brake_share: must be in (0, 1]");
  }
  if (!(std::isfinite(polar_radius_m) && polar_radius_m >= 0.0 &&
        std::isfinite(vfh_target_distance_m) && vfh_target_distance_m > 0.0)) {
    return absl::InvalidArgumentError("polar_radius_m >= 0 and vfh_target_distance_m > 0 required");
  }
  if (!(std::isfinite(tight_clearance_m) && std::isfinite(slow_clearance_m) &&
        tight_clearance_m < slow_clearance_m && slowest_share > 0.0 && slowest_share <= 1.0 &&
        std::isfinite(brake_lookahead_m) && brake_lookahead_m >= 0.0)) {
    return absl::InvalidArgumentError(
        "tight_clearance_m < slow_clearance_m, slowest_share in (0, 1] and brake_lookahead_m >= "
        "0 required");
  }
  if (absl::Status s = polar.Validate(); !s.ok()) return s;
  return vfh.Validate();
}

AckermannPurePursuit::AckermannPurePursuit(AckermannPurePursuitParams params,
                                           const RobotModel& model)
    : params_(params),
      limits_(model.limits),
      footprint_(model.FootprintBounds()),
      max_curvature_per_m_(model.wheelbase_m > 0.0
                               ? std::tan(model.limits.max_steering_rad) / model.wheelbase_m
                               : std::numeric_limits<double>::infinity()) {
  if (params_.avoid_obstacles) {
    VfhPlusParams vfh = params_.vfh;
    const double half_width_m = std::max(-footprint_.min().y(), footprint_.max().y());
    if (half_width_m > 0.0) vfh.robot_radius_m = half_width_m;
    if (std::isfinite(max_curvature_per_m_) && max_curvature_per_m_ > 0.0) {
      vfh.min_turning_radius_m = 1.0 / max_curvature_per_m_;
    }
    vfh_.emplace(vfh);
  }
}

bool AckermannPurePursuit::PathAheadObstructed(const Pose2& pose) const {
  if (obstacles_.empty()) return false;
  // The footprint widened by VFH+'s safety distance.
  Eigen::AlignedBox2d swept = footprint_;
  swept.min().array() -= params_.vfh.safety_distance_m;
  swept.max().array() += params_.vfh.safety_distance_m;
  const size_t end = pieces_[piece_].second;
  double last_checked_m = -1.0;
  for (size_t i = closest_; i <= end; ++i) {
    const double along_m = to_goal_m_[closest_] - to_goal_m_[i];
    if (along_m > params_.vfh_target_distance_m) break;
    if (i != end && along_m - last_checked_m < kObstructionStepM) continue;
    last_checked_m = along_m;
    const Pose2 from_path = path_[i].Inverse() * pose;
    for (const Eigen::Vector2d& p_in_base : obstacles_) {
      if (swept.contains(from_path.TransformPoint(p_in_base))) return true;
    }
  }
  return false;
}

double AckermannPurePursuit::ClearanceSpeedShare() const {
  if (clearance_m_.size() != path_.size()) return 1.0;
  double tightest_m = std::numeric_limits<double>::infinity();
  for (size_t i = closest_; i < path_.size(); ++i) {
    if (to_goal_m_[closest_] - to_goal_m_[i] > params_.brake_lookahead_m) break;
    tightest_m = std::min(tightest_m, clearance_m_[i]);
  }
  const double span_m = params_.slow_clearance_m - params_.tight_clearance_m;
  const double share = (tightest_m - params_.tight_clearance_m) / span_m;
  return params_.slowest_share + (1.0 - params_.slowest_share) * std::clamp(share, 0.0, 1.0);
}

Twist2 AckermannPurePursuit::Brake(double dt_s) {
  last_speed_mps_ = StepTowards(last_speed_mps_, 0.0, limits_.max_accel_mps2 * dt_s);
  return Twist2{last_speed_mps_, 0.0, 0.0};
}

std::optional<size_t> AckermannPurePursuit::FirstPoseAtLeast(const Pose2& pose,
                                                             double distance_m) const {
  for (size_t i = closest_; i <= pieces_[piece_].second; ++i) {
    if ((path_[i].translation() - pose.translation()).norm() >= distance_m) return i;
  }
  return std::nullopt;
}

void AckermannPurePursuit::SetPath(std::vector<Pose2> path) {
  path_ = std::move(path);
  to_goal_m_ = DistancesToGoal(path_);
  // Split where the direction of travel (step · heading) changes sign.
  pieces_.clear();
  piece_sign_.clear();
  int sign = 0;
  size_t begin = 0;
  for (size_t i = 0; i + 1 < path_.size(); ++i) {
    const Eigen::Vector2d step = path_[i + 1].translation() - path_[i].translation();
    if (step.norm() < kTinyStepM) continue;
    const Eigen::Vector2d heading(std::cos(path_[i].yaw_rad()), std::sin(path_[i].yaw_rad()));
    const int s = step.dot(heading) >= 0.0 ? 1 : -1;
    if (sign != 0 && s != sign) {
      pieces_.push_back({begin, i});
      piece_sign_.push_back(sign);
      begin = i;
    }
    sign = s;
  }
  pieces_.push_back({begin, path_.empty() ? 0 : path_.size() - 1});
  piece_sign_.push_back(sign == 0 ? 1 : sign);
  clearance_m_.clear();
  piece_ = 0;
  closest_ = 0;
  last_speed_mps_ = 0.0;
  done_ = path_.empty();
}

Twist2 AckermannPurePursuit::Step(const Pose2& pose, double dt_s) {
  if (done_ || path_.empty()) {
    last_speed_mps_ = 0.0;
    return Twist2{};
  }
  while (true) {
    const auto [begin, end] = pieces_[piece_];
    closest_ = std::clamp(closest_, begin, end);
    const ClosestPose closest = FindClosestPose(path_, pose, closest_, end + 1);
    closest_ = closest.index;
    const double best = closest.distance_m;
    cross_track_m_ = best;
    remaining_m_ = to_goal_m_[closest_] + best;
    // The piece's end reached: within tolerance, or passed (behind in the direction of travel).
    const Pose2& end_pose = path_[end];
    const Eigen::Vector2d end_local = pose.Inverse().TransformPoint(end_pose.translation());
    const int sign = piece_sign_[piece_];
    // Passed a little aside near the end of the piece also counts: driving on along the end's
    // heading would only take the car further away (the next piece, or the goal check, corrects
    // the offset).
    const bool passed = sign * end_local.x() <= 0.0;
    const bool near_end = to_goal_m_[closest_] - to_goal_m_[end] <= params_.passed_end_window_m;
    const bool reached = end_local.norm() <= params_.goal_tolerance_m ||
                         (passed && std::abs(end_local.y()) <= 2.0 * params_.goal_tolerance_m) ||
                         (passed && near_end && std::abs(end_local.y()) <= params_.passed_aside_m);
    if (!reached) break;
    if (piece_ + 1 == pieces_.size()) {
      done_ = true;
      last_speed_mps_ = 0.0;
      return Twist2{};
    }
    // A cusp: stop before driving the other way.
    if (std::abs(last_speed_mps_) > 1e-3) return Brake(dt_s);
    ++piece_;
  }
  const auto [begin, end] = pieces_[piece_];
  const int sign = piece_sign_[piece_];
  // The lookahead point: the first pose of the piece that far away, else beyond its end.
  const double lookahead = std::clamp(std::abs(last_speed_mps_) * params_.lookahead_time_s,
                                      params_.min_lookahead_m, params_.max_lookahead_m);
  const double straight_to_end_m = (path_[end].translation() - pose.translation()).norm();
  Eigen::Vector2d target;
  if (const std::optional<size_t> i = FirstPoseAtLeast(pose, lookahead)) {
    target = path_[*i].translation();
  } else {
    const Pose2& e = path_[end];
    const double beyond = lookahead - straight_to_end_m;
    target = e.translation() + sign * std::max(beyond, 0.0) *
                                   Eigen::Vector2d(std::cos(e.yaw_rad()), std::sin(e.yaw_rad()));
  }
  const Eigen::Vector2d local = pose.Inverse().TransformPoint(target);
  double curvature = 2.0 * local.y() / std::max(local.squaredNorm(), 1e-9);
  const double to_end_m = std::max(to_goal_m_[closest_] - to_goal_m_[end], straight_to_end_m);
  const double top = sign > 0 ? limits_.max_speed_mps : limits_.max_reverse_speed_mps;
  double speed = std::min(params_.desired_speed_mps * ClearanceSpeedShare(), top);
  blocked_ = false;
  const bool in_polar_zone =
      piece_ + 1 == pieces_.size() && straight_to_end_m <= params_.polar_radius_m;
  path_obstructed_ = !in_polar_zone && sign > 0 && vfh_.has_value() && PathAheadObstructed(pose);
  if (in_polar_zone) {
    const PolarPoseCommand polar = PolarMoveToPose(pose, path_[end], params_.polar, sign < 0);
    // Only where the car can do what the law asks: the goal well ahead and the curvature within
    // the lock (clamped, the law no longer converges and the car circles the goal).
    if (std::abs(polar.alpha_rad) < kPi / 4.0 &&
        std::abs(polar.curvature_per_m) <= max_curvature_per_m_) {
      curvature = polar.curvature_per_m;
      speed = std::min(speed, std::abs(polar.speed_mps));
    }
  } else if (path_obstructed_) {
    // What lies beyond the piece's end is for the next piece (or the map-checked goal).
    const double horizon_m = to_end_m + params_.vfh.robot_radius_m;
    std::vector<Eigen::Vector2d> near;
    for (const Eigen::Vector2d& p : obstacles_) {
      if (p.norm() <= horizon_m) near.push_back(p);
    }
    // The target: the piece's point vfh_target_distance_m ahead (else its end).
    const Eigen::Vector2d aim =
        path_[FirstPoseAtLeast(pose, params_.vfh_target_distance_m).value_or(end)].translation();
    const Eigen::Vector2d aim_local = pose.Inverse().TransformPoint(aim);
    const std::optional<VfhPlusDirection> direction =
        vfh_->Choose(near, std::atan2(aim_local.y(), aim_local.x()));
    if (!direction) {
      blocked_ = true;
      return Brake(dt_s);
    }
    curvature = 2.0 * std::sin(direction->direction_rad) / std::max(local.norm(), 1e-3);
    speed *= std::max(direction->clearance_m / params_.vfh.window_radius_m, kVfhSlowestShare);
  }
  curvature = std::clamp(curvature, -max_curvature_per_m_, max_curvature_per_m_);
  speed = std::min(speed, std::sqrt(2.0 * params_.brake_share * limits_.max_accel_mps2 * to_end_m));
  if (std::abs(curvature) > 1e-9) {
    speed = std::min(speed, limits_.max_yaw_rate_radps / std::abs(curvature));
  }
  speed = std::max(speed, kCreepSpeedMps);
  last_speed_mps_ = StepTowards(last_speed_mps_, sign * speed, limits_.max_accel_mps2 * dt_s);
  return Twist2{last_speed_mps_, 0.0, last_speed_mps_ * curvature};
}

}  // namespace fleetnav::agent
