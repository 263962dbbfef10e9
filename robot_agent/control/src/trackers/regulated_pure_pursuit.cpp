#include "fleetnav/robot_agent/control/trackers/regulated_pure_pursuit.hpp"

#include <algorithm>
#include <cmath>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/robot_agent/control/common/path_geometry.hpp"

namespace fleetnav::agent {
namespace {

/// Points closer than this behind the closest one are looked at when it moves on.
constexpr size_t kSearchWindow = 200;
/// Two path poses this close are one place: the planner turns in place there.
constexpr double kSamePlaceM = 0.01;
/// The robot turns a planned turn in place when it is this close to the turn's place: the
/// planner checked the sweep there, and a 2.3 m robot turning 0.1 m beside it (at 0.2 m, the
/// old radius) swung its corner into a fence the plan cleared by 0.09 m.
constexpr double kInPlaceRadiusM = 0.05;
/// ... or when it has come abreast of the place this close beside it.
constexpr double kAbreastRadiusM = 0.2;
/// A planned turn step counts as turned within this angle.
constexpr double kTurnStepToleranceRad = 0.05;
constexpr double kMinTurnRateRadps = 0.05;

/// The yaw error from `yaw_rad` to `target_rad`, turned the way the plan turns (`planned_rad`,
/// signed) when the shortest way is the other one and more than a quarter turn: the planner
/// checked the body's sweep that way round. A robot arriving a little beside the planned
/// heading faces a half turn whose shortest way is a coin toss, and the other way swung the
/// Lely's nose into a fence.
double PlannedWayError(double target_rad, double yaw_rad, double planned_rad) {
  double error = AngleDifference(target_rad, yaw_rad);
  if (planned_rad != 0.0 && error * planned_rad < 0.0 && std::abs(error) > kPi / 2.0) {
    error += std::copysign(2.0 * kPi, planned_rad);
  }
  return error;
}

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
  // The turns in place: where the sharp ones start, and the one the path ends with (if any).
  sharp_turns_.clear();
  final_turn_rad_ = 0.0;
  for (size_t i = 0; i + 1 < path_.size(); ++i) {
    if ((path_[i + 1].translation() - path_[i].translation()).norm() >= kSamePlaceM) continue;
    double turn_rad = 0.0;
    size_t j = i;
    while (j + 1 < path_.size() &&
           (path_[j + 1].translation() - path_[i].translation()).norm() < kSamePlaceM) {
      turn_rad += AngleDifference(path_[j + 1].yaw_rad(), path_[j].yaw_rad());
      ++j;
    }
    if (std::abs(turn_rad) > params_.rotate_to_heading_rad) sharp_turns_.push_back(i);
    if (j + 1 == path_.size()) final_turn_rad_ = turn_rad;
    i = j - 1;  // the loop's ++i moves on to j
  }
}

bool RegulatedPurePursuit::AtTurnPlace(const Pose2& pose, size_t turn) const {
  const Eigen::Vector2d to_place = path_[turn].translation() - pose.translation();
  if (to_place.norm() < kInPlaceRadiusM) return true;
  // Come abreast of it a little beside the path: chasing the place from there would turn the
  // robot round on the spot (any way) instead of the way the plan turns.
  if (turn == 0 || to_place.norm() >= kAbreastRadiusM) return false;
  const Eigen::Vector2d arriving = path_[turn].translation() - path_[turn - 1].translation();
  return to_place.dot(arriving) <= 0.0;
}

size_t RegulatedPurePursuit::NextSharpTurn(size_t from) const {
  const auto next = std::lower_bound(sharp_turns_.begin(), sharp_turns_.end(), from);
  return next == sharp_turns_.end() ? path_.size() - 1 : *next;
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
         AtTurnPlace(pose, closest_)) {
    const double error =
        PlannedWayError(path_[closest_ + 1].yaw_rad(), pose.yaw_rad(),
                        AngleDifference(path_[closest_ + 1].yaw_rad(), path_[closest_].yaw_rad()));
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
    const double error = PlannedWayError(goal.yaw_rad(), pose.yaw_rad(), final_turn_rad_);
    if (std::abs(error) <= params_.goal_tolerance_rad) {
      done_ = true;
      return Twist2{};
    }
    const double rate =
        std::clamp(params_.heading_gain_radps_per_rad * error, -max_yaw_rate, max_yaw_rate);
    const double min_rate = 0.03;
    return Twist2{0.0, 0.0, std::abs(rate) < min_rate ? std::copysign(min_rate, error) : rate};
  }

  // The lookahead point: the first path pose at least the lookahead distance away, but not past
  // a sharp turn in place ahead: the robot drives to the turn's place and turns there, where the
  // planner checked the sweep. Looking past it, it would turn early, where the corner of a
  // 2.3 m body can swing into a fence the plan kept clear of.
  const double lookahead = std::clamp(last_speed_mps_ * params_.lookahead_time_s,
                                      params_.min_lookahead_m, params_.max_lookahead_m);
  const size_t stop = NextSharpTurn(closest_);
  Eigen::Vector2d target = path_[stop].translation();
  for (size_t i = closest_; i <= stop; ++i) {
    if ((path_[i].translation() - pose.translation()).norm() >= lookahead) {
      target = path_[i].translation();
      break;
    }
  }
  const double to_stop_m = std::max(0.0, remaining_m_ - to_goal_m_[stop]);
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
  if (to_stop_m < params_.approach_distance_m) {
    speed *= to_stop_m / params_.approach_distance_m;
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
