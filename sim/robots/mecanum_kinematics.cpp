#include "fleetnav/sim/mecanum_kinematics.hpp"

#include <algorithm>

namespace fleetnav::sim {

MecanumWheelRates MecanumInverse(const RobotModel& model, const Twist2& twist) {
  const double k = 0.5 * (model.wheelbase_m + model.track_m);  // T_X + T_Y
  const double r = model.wheel_radius_m;
  const double w = twist.yaw_rate_radps;
  return {(twist.vx_mps - twist.vy_mps - k * w) / r, (twist.vx_mps + twist.vy_mps + k * w) / r,
          (twist.vx_mps + twist.vy_mps - k * w) / r, (twist.vx_mps - twist.vy_mps + k * w) / r};
}

Twist2 MecanumForward(const RobotModel& model, const MecanumWheelRates& q) {
  const double k = 0.5 * (model.wheelbase_m + model.track_m);
  const double r = model.wheel_radius_m;
  return Twist2{0.25 * r * (q[0] + q[1] + q[2] + q[3]), 0.25 * r * (-q[0] + q[1] + q[2] - q[3]),
                0.25 * r / k * (-q[0] + q[1] - q[2] + q[3])};
}

Twist2 ClampOmniTwist(const MotionLimits& limits, const Twist2& twist, double scale) {
  return Twist2{
      std::clamp(scale * twist.vx_mps, -limits.max_reverse_speed_mps, limits.max_speed_mps),
      std::clamp(scale * twist.vy_mps, -limits.max_lateral_speed_mps, limits.max_lateral_speed_mps),
      std::clamp(scale * twist.yaw_rate_radps, -limits.max_yaw_rate_radps,
                 limits.max_yaw_rate_radps)};
}

}  // namespace fleetnav::sim
