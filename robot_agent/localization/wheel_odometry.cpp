#include "fleetnav/robot_agent/wheel_odometry.hpp"

#include <cmath>

namespace fleetnav::agent {

WheelOdometry::WheelOdometry(const RobotModel& model, WheelOdometryParams params)
    : model_(model), params_(params) {}

double WheelOdometry::TicksToMeters(int64_t delta_ticks) const {
  const double circumference_m = 2.0 * 3.14159265358979323846 * model_.wheel_radius_m;
  return static_cast<double>(delta_ticks) / model_.encoder_ticks_per_rev * circumference_m;
}

void WheelOdometry::Update(const SensorFrame& frame) {
  const EncoderReading* left = frame.FindEncoder("left");
  const EncoderReading* right = frame.FindEncoder("right");
  if (left == nullptr || right == nullptr) return;
  if (!last_left_ticks_) {
    last_left_ticks_ = left->ticks;
    last_right_ticks_ = right->ticks;
    last_stamp_ns_ = frame.stamp_ns;
    return;
  }
  const double dt_s = static_cast<double>(frame.stamp_ns - last_stamp_ns_) * 1e-9;
  const double left_m = TicksToMeters(left->ticks - *last_left_ticks_);
  const double right_m = TicksToMeters(right->ticks - *last_right_ticks_);
  last_left_ticks_ = left->ticks;
  last_right_ticks_ = right->ticks;
  last_stamp_ns_ = frame.stamp_ns;
  if (dt_s <= 0.0) return;

  const double distance_m = 0.5 * (left_m + right_m);                   // eq. 3.1 × Δt
  const double encoder_dyaw_rad = (right_m - left_m) / model_.track_m;  // eq. 3.2 × Δt
  const double gyro_dyaw_rad = frame.imu.gyro_z_radps * dt_s;
  const double dyaw_rad =
      params_.gyro_weight * gyro_dyaw_rad + (1.0 - params_.gyro_weight) * encoder_dyaw_rad;

  const double mid_yaw = pose_.yaw_rad() + 0.5 * dyaw_rad;
  pose_ = Pose2(pose_.x_m() + distance_m * std::cos(mid_yaw),
                pose_.y_m() + distance_m * std::sin(mid_yaw), pose_.yaw_rad() + dyaw_rad);
  velocity_ = Twist2{distance_m / dt_s, 0.0, dyaw_rad / dt_s};
  distance_m_ += std::abs(distance_m);
}

}  // namespace fleetnav::agent
