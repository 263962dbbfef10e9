#include "fleetnav/sim/mecanum_kinematics.hpp"

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

}  // namespace fleetnav::sim
