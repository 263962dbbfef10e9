#include "fleetnav/robot_agent/fence_following_controller.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"

namespace fleetnav::agent {
namespace {

constexpr double kDistanceToleranceM = 0.002;
constexpr size_t kMinLinePoints = 10;
constexpr double kMinLineSpanM = 0.5;

}  // namespace

absl::Status FenceFollowingParams::Validate() const {
  if (!(std::isfinite(gain_radps_per_m) && gain_radps_per_m > 0.0)) {
    return absl::InvalidArgumentError("gain_radps_per_m: must be finite and > 0");
  }
  if (!(std::isfinite(max_yaw_rate_radps) && max_yaw_rate_radps > 0.0)) {
    return absl::InvalidArgumentError("max_yaw_rate_radps: must be finite and > 0");
  }
  if (!(std::isfinite(outlier_m) && outlier_m > 0.0)) {
    return absl::InvalidArgumentError("outlier_m: must be finite and > 0");
  }
  if (lost_after_ticks < 1 || found_after_ticks < 1) {
    return absl::InvalidArgumentError("lost_after_ticks, found_after_ticks: must be >= 1");
  }
  if (!(std::isfinite(line_memory_m) && line_memory_m > kMinLineSpanM)) {
    return absl::InvalidArgumentError(
        absl::StrCat("line_memory_m: must be finite and > ", kMinLineSpanM));
  }
  return absl::OkStatus();
}

FenceFollowingController::FenceFollowingController(const FenceNavigationAction& action,
                                                   const SensorMount& ultrasonic,
                                                   MotionProfile profile,
                                                   FenceFollowingParams params)
    : action_(action),
      ultrasonic_(ultrasonic),
      profile_(profile),
      params_(params),
      side_sign_(action.side == Side::kLeft ? 1.0 : -1.0) {}

double FenceFollowingController::DistanceToLine(const Pose2& sensor_in_map) const {
  const Eigen::Vector2d side_normal =
      side_sign_ * Eigen::Vector2d(-line_.direction.y(), line_.direction.x());
  return (line_.point - sensor_in_map.translation()).dot(side_normal);
}

void FenceFollowingController::FitLine(const Eigen::Vector2d& heading) {
  if (points_.size() < kMinLinePoints ||
      points_.back().travelled_m - points_.front().travelled_m < kMinLineSpanM) {
    return;
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const FencePoint& p : points_) mean += p.point_in_map;
  mean /= static_cast<double>(points_.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const FencePoint& p : points_) {
    const Eigen::Vector2d d = p.point_in_map - mean;
    scatter += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
  Eigen::Vector2d direction = solver.eigenvectors().col(1);  // largest eigenvalue
  if (direction.dot(heading) < 0.0) direction = -direction;
  line_.point = mean;
  line_.direction = direction.normalized();
}

ControlOutput FenceFollowingController::Step(const ControlInput& input) {
  const Pose2 sensor_in_map = input.pose_in_map * ultrasonic_.pose_in_base;
  const Eigen::Vector2d heading(std::cos(input.pose_in_map.yaw_rad()),
                                std::sin(input.pose_in_map.yaw_rad()));
  if (!started_) {
    started_ = true;
    last_odom_ = input.pose_in_odom;
    // Until the fence has been measured, assume it runs along the start heading at the set
    // distance from the sensor.
    const Eigen::Vector2d beam(std::cos(sensor_in_map.yaw_rad()),
                               std::sin(sensor_in_map.yaw_rad()));
    line_.point = sensor_in_map.translation() + action_.fence_distance_m * beam;
    line_.direction = heading;
  }
  const Pose2 moved = Between(last_odom_, input.pose_in_odom);
  travelled_m_ += std::hypot(moved.x_m(), moved.y_m());
  last_odom_ = input.pose_in_odom;

  ControlOutput out;
  const double remaining_m = action_.distance_m - travelled_m_;
  out.progress_fraction = std::clamp(travelled_m_ / action_.distance_m, 0.0, 1.0);
  out.mode = map_based_ ? NavigationMode::kFenceMapBased : NavigationMode::kFenceReactive;
  if (remaining_m <= kDistanceToleranceM) {
    out.done = true;
    out.progress_fraction = 1.0;
    return out;
  }

  // Is there a usable echo from the fence?
  const std::optional<double>& range =
      action_.side == Side::kLeft ? input.perception.fence_left_m : input.perception.fence_right_m;
  const double expected_m = DistanceToLine(sensor_in_map);
  const bool usable = range.has_value() && std::abs(*range - expected_m) < params_.outlier_m;
  if (usable) {
    const Eigen::Vector2d beam(std::cos(sensor_in_map.yaw_rad()),
                               std::sin(sensor_in_map.yaw_rad()));
    points_.push_back({sensor_in_map.translation() + *range * beam, travelled_m_});
    while (!points_.empty() && points_.front().travelled_m < travelled_m_ - params_.line_memory_m) {
      points_.pop_front();
    }
    FitLine(heading);
    ++present_ticks_;
    missing_ticks_ = 0;
  } else {
    ++missing_ticks_;
    present_ticks_ = 0;
  }
  if (!map_based_ && missing_ticks_ >= params_.lost_after_ticks) {
    map_based_ = true;
    out.mode_reason = absl::StrCat("no echo from the ", action_.side == Side::kLeft ? "left" : "right",
                                   " fence for ", missing_ticks_, " ticks");
  } else if (map_based_ && present_ticks_ >= params_.found_after_ticks) {
    map_based_ = false;
    out.mode_reason = "the fence answers again";
  }
  out.mode = map_based_ ? NavigationMode::kFenceMapBased : NavigationMode::kFenceReactive;

  // Reactive: the measured range; map-based (and single missing readings): the estimate's
  // distance to the fitted fence line.
  const double distance_m = (!map_based_ && usable) ? *range : expected_m;
  const double error_m = distance_m - action_.fence_distance_m;
  const double yaw_rate = std::clamp(side_sign_ * params_.gain_radps_per_m * error_m,
                                     -params_.max_yaw_rate_radps, params_.max_yaw_rate_radps);

  double speed = std::min({action_.speed_mps, last_speed_mps_ + profile_.accel_mps2 * input.dt_s,
                           std::sqrt(2.0 * profile_.decel_mps2 * remaining_m)});
  speed = std::max(speed, std::min(profile_.min_speed_mps, action_.speed_mps));
  last_speed_mps_ = speed;
  out.command = Twist2{speed, 0.0, yaw_rate};
  return out;
}

}  // namespace fleetnav::agent
