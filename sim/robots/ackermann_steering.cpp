#include "fleetnav/sim/ackermann_steering.hpp"

#include <algorithm>
#include <cmath>

namespace fleetnav::sim {

absl::StatusOr<AckermannTarget> AckermannTargetOf(const RobotModel& model,
                                                  const DriveCommand& drive, double scale,
                                                  double previous_steering_rad) {
  double speed = 0.0;
  double steering = previous_steering_rad;
  if (const auto* twist = std::get_if<Twist2>(&drive)) {
    speed = twist->vx_mps;
    if (std::abs(speed) > 1e-3) {
      steering = std::atan(twist->yaw_rate_radps * model.wheelbase_m / speed);
    }
  } else if (const auto* ackermann = std::get_if<AckermannDrive>(&drive)) {
    speed = ackermann->speed_mps;
    steering = ackermann->steering_rad;
  } else {
    return absl::InvalidArgumentError(
        "the robot is Ackermann: send a twist or an Ackermann command, not wheel speeds");
  }
  if (!std::isfinite(speed) || !std::isfinite(steering)) {
    return absl::InvalidArgumentError("Ackermann command: not finite");
  }
  const MotionLimits& limits = model.limits;
  return AckermannTarget{
      std::clamp(scale * speed, -limits.max_reverse_speed_mps, limits.max_speed_mps),
      std::clamp(steering, -limits.max_steering_rad, limits.max_steering_rad)};
}

FrontWheelAngles AckermannFrontWheelAngles(double steering_rad, double wheelbase_m,
                                           double track_m) {
  const double t = std::tan(steering_rad);
  const double half = 0.5 * track_m;
  return FrontWheelAngles{std::atan2(wheelbase_m * t, wheelbase_m - half * t),
                          std::atan2(wheelbase_m * t, wheelbase_m + half * t)};
}

}  // namespace fleetnav::sim
