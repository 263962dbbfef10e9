#include "fleetnav/robot_agent/control/modes/fence_following_controller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"

namespace fleetnav::agent {
namespace {

constexpr double kDistanceToleranceM = 0.002;
constexpr double kMinLineMemoryM = 0.5;

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
  if (!(std::isfinite(start_offset_m) && start_offset_m >= 0.0 && std::isfinite(start_search_m) &&
        start_search_m >= 0.0)) {
    return absl::InvalidArgumentError("start_offset_m, start_search_m: must be finite and >= 0");
  }
  if (lost_after_ticks < 1 || found_after_ticks < 1) {
    return absl::InvalidArgumentError("lost_after_ticks, found_after_ticks: must be >= 1");
  }
  if (!(std::isfinite(line_memory_m) && line_memory_m > kMinLineMemoryM)) {
    return absl::InvalidArgumentError(
        absl::StrCat("line_memory_m: must be finite and > ", kMinLineMemoryM));
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
      side_sign_(action.side == Side::kLeft ? 1.0 : -1.0),
      line_(params.line_memory_m) {}

double FenceFollowingController::DistanceToLine(const Pose2& sensor_in_map) const {
  return -side_sign_ * line_.SignedDistance(sensor_in_map.translation());
}

ControlOutput FenceFollowingController::Step(const ControlInput& input) {
  const Pose2 sensor_in_map = input.pose_in_map * ultrasonic_.pose_in_base;
  const Eigen::Vector2d heading(std::cos(input.pose_in_map.yaw_rad()),
                                std::sin(input.pose_in_map.yaw_rad()));
  const Eigen::Vector2d beam(std::cos(sensor_in_map.yaw_rad()), std::sin(sensor_in_map.yaw_rad()));
  if (!started_) {
    started_ = true;
    last_odom_ = input.pose_in_odom;
    // Until the fence has been measured, assume it runs along the start heading at the set
    // distance from the sensor.
    line_.Assume(sensor_in_map.translation() + action_.fence_distance_m * beam, heading);
  }
  const Pose2 moved = Between(last_odom_, input.pose_in_odom);
  travelled_m_ += std::hypot(moved.x_m(), moved.y_m());
  last_odom_ = input.pose_in_odom;
  // A leg may start off its distance and close in: over its first metre the first echo within
  // start_offset_m of the set distance places the fence (a single dropout on the first tick
  // must not leave the robot steering on the assumed line).
  const std::optional<double>& echo =
      action_.side == Side::kLeft ? input.perception.fence_left_m : input.perception.fence_right_m;
  if (!fence_placed_ && travelled_m_ <= params_.start_search_m && echo.has_value() &&
      std::abs(*echo - action_.fence_distance_m) <= params_.start_offset_m) {
    line_.Assume(sensor_in_map.translation() + *echo * beam, heading);
    fence_placed_ = true;
  }

  ControlOutput out;
  // distance_m = 0: until the end condition (a marker) says so.
  const bool limited = action_.distance_m > 0.0;
  const double remaining_m =
      limited ? action_.distance_m - travelled_m_ : std::numeric_limits<double>::infinity();
  out.progress_fraction = limited ? std::clamp(travelled_m_ / action_.distance_m, 0.0, 1.0) : 0.0;
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
    line_.Add(sensor_in_map.translation() + *range * beam, travelled_m_, heading);
    ++present_ticks_;
    missing_ticks_ = 0;
  } else {
    ++missing_ticks_;
    present_ticks_ = 0;
  }
  if (!map_based_ && missing_ticks_ >= params_.lost_after_ticks) {
    map_based_ = true;
    out.mode_reason =
        absl::StrCat("no echo from the ", action_.side == Side::kLeft ? "left" : "right",
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

  const double speed =
      profile_.NextSpeed(action_.speed_mps, last_speed_mps_, remaining_m, input.dt_s);
  last_speed_mps_ = speed;
  out.command = Twist2{speed, 0.0, yaw_rate};
  return out;
}

}  // namespace fleetnav::agent
