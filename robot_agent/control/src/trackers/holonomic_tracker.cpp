#include "fleetnav/robot_agent/control/trackers/holonomic_tracker.hpp"

#include <algorithm>
#include <cmath>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/robot_agent/control/common/path_geometry.hpp"

namespace fleetnav::agent {
namespace {

/// Points closer than this behind the closest one are looked at when it moves on.
constexpr size_t kSearchWindow = 200;
/// Two path poses this close are one place: the path turns in place there.
constexpr double kSamePlaceM = 0.01;
/// A planned turn in place is turned once the platform is this close to its place.
constexpr double kInPlaceRadiusM = 0.1;
constexpr double kTurnStepToleranceRad = 0.05;
/// The path's turning rate is taken over this much of it ahead of the closest pose.
constexpr double kTurnLookM = 0.2;
/// Turning along the path uses at most this share of the yaw-rate limit (the rest corrects).
constexpr double kYawRateShare = 0.8;
/// Slowest translation while still away from the goal, so the approach ends in finite time.
constexpr double kCreepSpeedMps = 0.02;

}  // namespace

absl::Status HolonomicTrackerParams::Validate() const {
  for (double v : {desired_speed_mps, carrot_distance_m, position_gain_per_s, heading_gain_per_s,
                   heading_stop_rad, goal_tolerance_m, goal_tolerance_rad}) {
    if (!(std::isfinite(v) && v > 0.0)) {
      return absl::InvalidArgumentError("holonomic tracker parameters: must be finite and > 0");
    }
  }
  if (!(brake_share > 0.0 && brake_share <= 1.0)) {
    return absl::InvalidArgumentError("brake_share: must be in (0, 1]");
  }
  return absl::OkStatus();
}

HolonomicTracker::HolonomicTracker(HolonomicTrackerParams params, MotionLimits limits)
    : params_(params), limits_(limits) {}

void HolonomicTracker::SetPath(std::vector<Pose2> path) {
  path_ = std::move(path);
  to_goal_m_ = DistancesToGoal(path_);
  closest_ = 0;
  done_ = path_.empty();
}

size_t HolonomicTracker::NextStop(size_t from) const {
  for (size_t i = from; i + 1 < path_.size(); ++i) {
    if ((path_[i + 1].translation() - path_[i].translation()).norm() < kSamePlaceM &&
        std::abs(AngleDifference(path_[i + 1].yaw_rad(), path_[i].yaw_rad())) >
            kTurnStepToleranceRad) {
      return i;
    }
  }
  return path_.size() - 1;
}

Twist2 HolonomicTracker::Step(const Pose2& pose, double dt_s) {
  if (done_ || path_.empty()) {
    last_command_ = Twist2{};
    return last_command_;
  }
  // The closest path pose, searched forward from the last one.
  const ClosestPose closest = FindClosestPose(path_, pose, closest_, closest_ + kSearchWindow);
  closest_ = closest.index;
  const double best = closest.distance_m;
  cross_track_m_ = best;
  remaining_m_ = to_goal_m_[closest_] + best;

  // Turns in place are turned where they were planned: the planner checked that sweep.
  Eigen::Vector2d velocity_in_map = Eigen::Vector2d::Zero();
  double yaw_target = pose.yaw_rad();
  double yaw_feed_forward_radps = 0.0;
  bool turning_in_place = false;
  while (closest_ + 1 < path_.size() &&
         (path_[closest_ + 1].translation() - path_[closest_].translation()).norm() < kSamePlaceM &&
         (pose.translation() - path_[closest_].translation()).norm() < kInPlaceRadiusM) {
    if (std::abs(AngleDifference(path_[closest_ + 1].yaw_rad(), pose.yaw_rad())) <=
        kTurnStepToleranceRad) {
      ++closest_;
      continue;
    }
    // Hold the place while turning.
    velocity_in_map =
        params_.position_gain_per_s * (path_[closest_].translation() - pose.translation());
    yaw_target = path_[closest_ + 1].yaw_rad();
    turning_in_place = true;
    break;
  }

  const Pose2& goal = path_.back();
  const double goal_distance = (goal.translation() - pose.translation()).norm();
  if (!turning_in_place) {
    const size_t stop = NextStop(closest_);
    // At the goal pose: done once the platform can stop within this tick.
    if (stop + 1 == path_.size() && goal_distance <= params_.goal_tolerance_m &&
        std::abs(AngleDifference(goal.yaw_rad(), pose.yaw_rad())) <= params_.goal_tolerance_rad &&
        std::hypot(last_command_.vx_mps, last_command_.vy_mps) <= limits_.max_accel_mps2 * dt_s &&
        std::abs(last_command_.yaw_rate_radps) <= limits_.max_yaw_accel_radps2 * dt_s) {
      done_ = true;
      last_command_ = Twist2{};
      return last_command_;
    }
    // The carrot: a little ahead along the path, never past the next stop.
    size_t carrot = closest_;
    while (carrot < stop && to_goal_m_[closest_] - to_goal_m_[carrot] < params_.carrot_distance_m) {
      ++carrot;
    }
    const Eigen::Vector2d to_carrot = path_[carrot].translation() - pose.translation();
    const double to_stop_m = std::max(to_goal_m_[closest_] - to_goal_m_[stop],
                                      (path_[stop].translation() - pose.translation()).norm());
    double speed = std::min(params_.desired_speed_mps, limits_.max_speed_mps);
    speed =
        std::min(speed, std::sqrt(2.0 * params_.brake_share * limits_.max_accel_mps2 * to_stop_m));
    // The path's turning per metre just ahead: the platform turns as it moves along, no
    // sooner (the spline's sweep was checked with the yaw where it is planned), and no faster
    // than its yaw-rate limit allows at this speed.
    size_t ahead = closest_;
    while (ahead < stop && to_goal_m_[closest_] - to_goal_m_[ahead] < kTurnLookM) ++ahead;
    const double ahead_m = to_goal_m_[closest_] - to_goal_m_[ahead];
    const double turn_per_m =
        ahead_m > 1e-6
            ? AngleDifference(path_[ahead].yaw_rad(), path_[closest_].yaw_rad()) / ahead_m
            : 0.0;
    if (std::abs(turn_per_m) > 1e-6) {
      speed = std::min(speed, kYawRateShare * limits_.max_yaw_rate_radps / std::abs(turn_per_m));
    }
    // Off the path's yaw here: slow down until the platform has turned.
    const double yaw_error_here = AngleDifference(path_[closest_].yaw_rad(), pose.yaw_rad());
    speed *= std::clamp(1.0 - std::abs(yaw_error_here) / params_.heading_stop_rad, 0.0, 1.0);
    const double carrot_m = to_carrot.norm();
    const bool at_goal = stop + 1 == path_.size() && goal_distance <= params_.goal_tolerance_m;
    if (carrot_m > 1e-6) {
      if (!at_goal)
        speed = std::max(speed, std::min(kCreepSpeedMps, carrot_m / dt_s));
      else
        speed = 0.0;
      velocity_in_map = speed * to_carrot / carrot_m;
    }
    // Standing at the goal's place, turn onto the goal's yaw: the closest path pose may be one
    // a little before the end, at another yaw, and holding that would never end.
    yaw_target = at_goal ? goal.yaw_rad() : path_[closest_].yaw_rad();
    yaw_feed_forward_radps = turn_per_m * speed;
  }

  // Into the body frame, within the model's limits (translation scaled as a whole).
  const double c = std::cos(pose.yaw_rad());
  const double s = std::sin(pose.yaw_rad());
  Twist2 command;
  command.vx_mps = c * velocity_in_map.x() + s * velocity_in_map.y();
  command.vy_mps = -s * velocity_in_map.x() + c * velocity_in_map.y();
  double scale = 1.0;
  const double speed = std::hypot(command.vx_mps, command.vy_mps);
  if (speed > limits_.max_speed_mps) scale = std::min(scale, limits_.max_speed_mps / speed);
  if (std::abs(command.vy_mps) > limits_.max_lateral_speed_mps) {
    scale = std::min(scale, limits_.max_lateral_speed_mps / std::abs(command.vy_mps));
  }
  if (command.vx_mps < -limits_.max_reverse_speed_mps) {
    scale = std::min(scale, limits_.max_reverse_speed_mps / -command.vx_mps);
  }
  command.vx_mps *= scale;
  command.vy_mps *= scale;
  const double yaw_error = AngleDifference(yaw_target, pose.yaw_rad());
  command.yaw_rate_radps =
      std::clamp(yaw_feed_forward_radps + params_.heading_gain_per_s * yaw_error,
                 -limits_.max_yaw_rate_radps, limits_.max_yaw_rate_radps);
  // Acceleration limits: the change of the translation as a vector, the yaw rate alone.
  const double dvx = command.vx_mps - last_command_.vx_mps;
  const double dvy = command.vy_mps - last_command_.vy_mps;
  const double dv = std::hypot(dvx, dvy);
  const double max_dv = limits_.max_accel_mps2 * dt_s;
  if (dv > max_dv && dv > 0.0) {
    command.vx_mps = last_command_.vx_mps + dvx * max_dv / dv;
    command.vy_mps = last_command_.vy_mps + dvy * max_dv / dv;
  }
  const double max_dw = limits_.max_yaw_accel_radps2 * dt_s;
  command.yaw_rate_radps = std::clamp(command.yaw_rate_radps, last_command_.yaw_rate_radps - max_dw,
                                      last_command_.yaw_rate_radps + max_dw);
  last_command_ = command;
  return command;
}

}  // namespace fleetnav::agent
