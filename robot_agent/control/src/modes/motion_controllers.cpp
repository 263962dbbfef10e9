#include "fleetnav/robot_agent/control/modes/motion_controllers.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {
namespace {

constexpr double kDistanceToleranceM = 0.002;

double Clamp(double value, double limit) { return std::clamp(value, -limit, limit); }

}  // namespace

absl::Status MotionProfile::Validate() const {
  for (const auto& [name, value] :
       {std::pair{"accel_mps2", accel_mps2}, std::pair{"decel_mps2", decel_mps2},
        std::pair{"yaw_accel_radps2", yaw_accel_radps2}}) {
    if (!(std::isfinite(value) && value > 0.0)) {
      return absl::InvalidArgumentError(absl::StrCat(name, ": must be finite and > 0"));
    }
  }
  if (!(min_speed_mps >= 0.0 && min_yaw_rate_radps >= 0.0)) {
    return absl::InvalidArgumentError("min_speed_mps, min_yaw_rate_radps: must be >= 0");
  }
  return absl::OkStatus();
}

double MotionProfile::NextSpeed(double target_mps, double last_mps, double remaining_m,
                                double dt_s) const {
  const double speed = std::min({target_mps, last_mps + accel_mps2 * dt_s,
                                 std::sqrt(2.0 * decel_mps2 * std::max(remaining_m, 0.0))});
  return std::max(speed, std::min(min_speed_mps, target_mps));
}

absl::Status HeadingPidGains::Validate() const {
  if (!(std::isfinite(kp) && std::isfinite(ki) && std::isfinite(kd) &&
        std::isfinite(cross_track_gain) && kp >= 0 && ki >= 0 && kd >= 0 &&
        cross_track_gain >= 0)) {
    return absl::InvalidArgumentError("heading PID gains: must be finite and >= 0");
  }
  return absl::OkStatus();
}

StraightController::StraightController(double distance_m, double speed_mps, MotionProfile profile,
                                       HeadingPidGains gains)
    : distance_m_(distance_m), speed_mps_(speed_mps), profile_(profile), gains_(gains) {}

ControlOutput StraightController::Step(const ControlInput& input) {
  const Pose2& pose_in_odom = input.pose_in_odom;
  const double dt_s = input.dt_s;
  if (!started_) {
    start_ = pose_in_odom;
    started_ = true;
  }
  const Pose2 local = Between(start_, pose_in_odom);  // x along the start heading, y lateral
  const double remaining_m = distance_m_ - local.x_m();
  ControlOutput out;
  out.mode = NavigationMode::kStraight;
  out.progress_fraction = std::clamp(local.x_m() / distance_m_, 0.0, 1.0);
  if (remaining_m <= kDistanceToleranceM) {
    out.done = true;
    out.progress_fraction = 1.0;
    return out;
  }
  const double speed = profile_.NextSpeed(speed_mps_, last_speed_mps_, remaining_m, dt_s);
  last_speed_mps_ = speed;

  // Heading PID toward the start heading, plus a pull back onto the start line.
  const double heading_error = AngleDifference(start_.yaw_rad(), pose_in_odom.yaw_rad());
  integral_ = Clamp(integral_ + heading_error * dt_s, 0.2);
  const double derivative = dt_s > 0.0 ? (heading_error - last_error_) / dt_s : 0.0;
  last_error_ = heading_error;
  const double yaw_rate = gains_.kp * heading_error + gains_.ki * integral_ +
                          gains_.kd * derivative - gains_.cross_track_gain * local.y_m();
  out.command = Twist2{speed, 0.0, Clamp(yaw_rate, 0.3)};
  return out;
}

TurnController::TurnController(double angle_rad, double yaw_rate_radps, MotionProfile profile,
                               double tolerance_rad)
    : angle_rad_(angle_rad),
      yaw_rate_radps_(std::abs(yaw_rate_radps)),
      profile_(profile),
      tolerance_rad_(tolerance_rad) {}

ControlOutput TurnController::Step(const ControlInput& input) {
  const Pose2& pose_in_odom = input.pose_in_odom;
  const double dt_s = input.dt_s;
  if (!started_) {
    last_yaw_rad_ = pose_in_odom.yaw_rad();
    started_ = true;
  }
  // Turns may exceed π, so accumulate the unwrapped angle turned so far.
  turned_rad_ += AngleDifference(pose_in_odom.yaw_rad(), last_yaw_rad_);
  last_yaw_rad_ = pose_in_odom.yaw_rad();
  const double error = angle_rad_ - turned_rad_;
  ControlOutput out;
  out.mode = NavigationMode::kTurn;
  out.progress_fraction =
      std::clamp(1.0 - std::abs(error) / std::max(std::abs(angle_rad_), 1e-9), 0.0, 1.0);
  if (std::abs(error) <= tolerance_rad_) {
    out.done = true;
    out.progress_fraction = 1.0;
    return out;
  }
  double rate = std::min({yaw_rate_radps_, last_rate_radps_ + profile_.yaw_accel_radps2 * dt_s,
                          std::sqrt(2.0 * profile_.yaw_accel_radps2 * std::abs(error))});
  rate = std::max(rate, std::min(profile_.min_yaw_rate_radps, yaw_rate_radps_));
  last_rate_radps_ = rate;
  out.command = Twist2{0.0, 0.0, std::copysign(rate, error)};
  return out;
}

}  // namespace fleetnav::agent
