#include "fleetnav/robot_agent/regulated_pure_pursuit.hpp"

#include <algorithm>
#include <cmath>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/robot_agent/path_geometry.hpp"

namespace fleetnav::agent {
namespace {

/// Points closer than this behind the closest one are looked at when it moves on.
constexpr size_t kSearchWindow = 200;
/// Two path poses this close are one place: the planner turns in place there.
constexpr double kSamePlaceM = 0.01;
/// The robot turns a planned turn in place when it is this close to the turn's place.
constexpr double kInPlaceRadiusM = 0.2;
/// A planned turn step counts as turned within this angle.
constexpr double kTurnStepToleranceRad = 0.05;
constexpr double kMinTurnRateRadps = 0.05;

}  // namespace

absl::Status RegulatedPurePursuitParams::Validate() const {
  for (double v :
       {desired_speed_mps, lookahead_time_s, min_lookahead_m, max_lookahead_m,
        regulated_min_radius_m, min_regulated_speed_mps, approach_distance_m, rotate_to_heading_rad,
        heading_gain_radps_per_rad, goal_tolerance_m, goal_tolerance_rad}) {
    if (!(std::isfinite(v) && v > 0.0)) {
      return absl::InvalidArgumentError(
          "regulated pure pursuit parameters: must be finite and > 0");
    }
  }
  if (min_lookahead_m > max_lookahead_m) {
    return absl::InvalidArgumentError("min_lookahead_m: must be <= max_lookahead_m");
  }
  return absl::OkStatus();
}

RegulatedPurePursuit::RegulatedPurePursuit(RegulatedPurePursuitParams params, MotionLimits limits)
    : params_(params), limits_(limits) {}

void RegulatedPurePursuit::SetPath(std::vector<Pose2> path) {
  path_ = std::move(path);
  to_goal_m_ = DistancesToGoal(path_);
  closest_ = 0;
  done_ = path_.empty();
}

Twist2 RegulatedPurePursuit::Step(const Pose2& pose, double dt_s) {
  if (done_ || path_.empty()) {
    last_speed_mps_ = 0.0;
    return Twist2{};
  }
  // The closest path pose, searched forward from the last one.
  const ClosestPose closest = FindClosestPose(path_, pose, closest_, closest_ + kSearchWindow);
  closest_ = closest.index;
  const double best = closest.distance_m;
  cross_track_m_ = best;
  const Pose2& goal = path_.back();
  const double goal_distance = (goal.translation() - pose.translation()).norm();
  remaining_m_ = to_goal_m_[closest_] + best;

  const double max_yaw_rate = limits_.max_yaw_rate_radps;
  // Turns in place in the path are turned as planned, step by step: the planner checked the
  // footprint's sweep that way round, not the other.
  while (closest_ + 1 < path_.size() &&
         (path_[closest_ + 1].translation() - path_[closest_].translation()).norm() < kSamePlaceM &&
         (pose.translation() - path_[closest_].translation()).norm() < kInPlaceRadiusM) {
    const double error = AngleDifference(path_[closest_ + 1].yaw_rad(), pose.yaw_rad());
    if (std::abs(error) <= kTurnStepToleranceRad) {
      ++closest_;
      continue;
    }
    last_speed_mps_ = 0.0;
    const double rate = std::clamp(params_.heading_gain_radps_per_rad * std::abs(error) + 0.1,
                                   kMinTurnRateRadps, max_yaw_rate);
    return Twist2{0.0, 0.0, std::copysign(rate, error)};
  }
  // At the goal: turn in place onto its yaw.
  if (goal_distance <= params_.goal_tolerance_m && closest_ + 1 >= path_.size()) {
    last_speed_mps_ = 0.0;
    const double error = AngleDifference(goal.yaw_rad(), pose.yaw_rad());
    if (std::abs(error) <= params_.goal_tolerance_rad) {
      done_ = true;
      return Twist2{};
    }
    const double rate =
        std::clamp(params_.heading_gain_radps_per_rad * error, -max_yaw_rate, max_yaw_rate);
    const double min_rate = 0.03;
    return Twist2{0.0, 0.0, std::abs(rate) < min_rate ? std::copysign(min_rate, error) : rate};
  }

  // The lookahead point: the first path pose at least the lookahead distance away.
  const double lookahead = std::clamp(last_speed_mps_ * params_.lookahead_time_s,
                                      params_.min_lookahead_m, params_.max_lookahead_m);
  Eigen::Vector2d target = goal.translation();
  for (size_t i = closest_; i < path_.size(); ++i) {
    if ((path_[i].translation() - pose.translation()).norm() >= lookahead) {
      target = path_[i].translation();
      break;
    }
  }
  const Eigen::Vector2d local = pose.Inverse().TransformPoint(target);
  const double bearing = std::atan2(local.y(), local.x());
  if (std::abs(bearing) > params_.rotate_to_heading_rad) {
    last_speed_mps_ = 0.0;
    return Twist2{
        0.0, 0.0,
        std::clamp(params_.heading_gain_radps_per_rad * bearing, -max_yaw_rate, max_yaw_rate)};
  }
  const double curvature = 2.0 * local.y() / std::max(local.squaredNorm(), 1e-9);
  double speed = std::min(params_.desired_speed_mps, limits_.max_speed_mps);
  const double radius = std::abs(curvature) > 1e-9 ? 1.0 / std::abs(curvature) : 1e9;
  if (radius < params_.regulated_min_radius_m) speed *= radius / params_.regulated_min_radius_m;
  if (remaining_m_ < params_.approach_distance_m) {
    speed *= remaining_m_ / params_.approach_distance_m;
  }
  speed = std::max(speed, params_.min_regulated_speed_mps);
  speed = std::min(speed, last_speed_mps_ + limits_.max_accel_mps2 * dt_s);
  double yaw_rate = speed * curvature;
  if (std::abs(yaw_rate) > max_yaw_rate) {  // keep the curvature, slow down
    speed *= max_yaw_rate / std::abs(yaw_rate);
    yaw_rate = std::copysign(max_yaw_rate, yaw_rate);
  }
  last_speed_mps_ = speed;
  return Twist2{speed, 0.0, yaw_rate};
}

}  // namespace fleetnav::agent
