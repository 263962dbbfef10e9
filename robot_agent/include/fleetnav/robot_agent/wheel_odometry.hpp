#pragma once

#include <cstdint>
#include <optional>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/core/sensor_frame.hpp"

namespace fleetnav::agent {

struct WheelOdometryParams {
  /// Weight of the gyro in the yaw rate (1 = gyro only, 0 = encoders only). The gyro is far
  /// better on yaw than wheel differences on a heavy robot with a caster.
  double gyro_weight = 1.0;
};

/// Differential-drive odometry from cumulative encoder ticks (Lely thesis eq. 3.1–3.4):
/// v_wheel = Δticks / (Δt · ticks_per_rev) · 2πr, v = (v_l + v_r)/2, ω = (v_r − v_l)/L, with the
/// yaw rate blended with the gyro. Integrates pose_in_odom with the midpoint (second-order
/// Runge–Kutta) rule. Not thread-safe.
class WheelOdometry {
 public:
  WheelOdometry(const RobotModel& model, WheelOdometryParams params = {});

  /// Consumes one frame; the first frame only sets the reference ticks.
  void Update(const SensorFrame& frame);
  const Pose2& pose_in_odom() const { return pose_; }
  const Twist2& velocity() const { return velocity_; }
  /// Total path length driven (m), forward and backward both counted positive.
  double distance_travelled_m() const { return distance_m_; }

 private:
  double TicksToMeters(int64_t delta_ticks) const;

  RobotModel model_;
  WheelOdometryParams params_;
  std::optional<int64_t> last_left_ticks_;
  std::optional<int64_t> last_right_ticks_;
  int64_t last_stamp_ns_ = 0;
  Pose2 pose_;
  Twist2 velocity_;
  double distance_m_ = 0.0;
};

}  // namespace fleetnav::agent
