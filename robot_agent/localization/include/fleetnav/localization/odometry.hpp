#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"

namespace fleetnav::localization {

/// A body-frame motion over one interval: forward, lateral (omni only) and yaw increments.
struct BodyIncrement {
  double forward_m = 0.0;
  double lateral_m = 0.0;
  double yaw_rad = 0.0;
};

/// Integrates a body increment onto a pose with the midpoint (second-order Runge–Kutta) rule:
/// the translation is applied along the heading at the middle of the interval.
Pose2 IntegrateIncrement(const Pose2& pose, const BodyIncrement& increment);

/// Parameters of a differential drive's encoders. Defaults: the Lely Vector (thesis ch. 3).
struct DiffDriveOdometryParams {
  double wheel_radius_m = 0.15;  ///< Ø 300 mm wheels
  double track_m = 0.92;         ///< distance between the wheels
  int encoder_ticks_per_rev = 4096;
  absl::Status Validate() const;
};

/// Differential-drive odometry from cumulative encoder ticks (Lely thesis eq. 3.1–3.4): each
/// wheel's arc is 2πr·Δticks/ticks_per_rev, the body advances by their mean and turns by their
/// difference over the track. The first call only latches the tick counts. Value type.
class DiffDriveOdometry {
 public:
  explicit DiffDriveOdometry(const DiffDriveOdometryParams& params) : params_(params) {}
  /// Adds the motion since the previous ticks; returns the body increment.
  BodyIncrement Update(int64_t left_ticks, int64_t right_ticks);
  const Pose2& pose_in_odom() const { return pose_; }

 private:
  DiffDriveOdometryParams params_;
  std::optional<std::array<int64_t, 2>> last_ticks_;
  Pose2 pose_;
};

/// Mecanum platform geometry in the KUKA thesis's notation (ch. 4): r1 the wheel radius and r2
/// the roller radius (the thesis's effective radius is r1 + r2), T_X half the wheelbase, T_Y
/// half the track. Defaults: the KUKA-like store platform.
struct MecanumOdometryParams {
  double wheel_radius_m = 0.076;   ///< r1
  double roller_radius_m = 0.0;    ///< r2; 0 when r1 is already the effective radius
  double half_wheelbase_m = 0.24;  ///< T_X
  double half_track_m = 0.19;      ///< T_Y
  absl::Status Validate() const;
};

/// Mecanum forward kinematics (KUKA thesis eq. 4.14–4.17), wheels numbered 1 front-left,
/// 2 front-right, 3 rear-left, 4 rear-right:
///   v_x = (r1+r2)/4 · (φ1 + φ2 + φ3 + φ4), v_y = (r1+r2)/4 · (−φ1 + φ2 + φ3 − φ4),
///   ω = (r1+r2)/(4(T_X+T_Y)) · (−φ1 + φ2 − φ3 + φ4).
/// Update() takes wheel angle increments (rad) and integrates them (the thesis's ch. 8 odometry
/// model with the midpoint rule). Value type.
class MecanumOdometry {
 public:
  explicit MecanumOdometry(const MecanumOdometryParams& params) : params_(params) {}
  /// Body twist (v_x, v_y, ω) for wheel rates φ̇1..φ̇4 in rad/s.
  Eigen::Vector3d ForwardKinematics(const std::array<double, 4>& wheel_radps) const;
  /// Inverse kinematics (thesis eq. 4.5–4.8): wheel rates for a body twist.
  std::array<double, 4> InverseKinematics(const Eigen::Vector3d& twist) const;
  BodyIncrement Update(const std::array<double, 4>& wheel_increments_rad);
  const Pose2& pose_in_odom() const { return pose_; }

 private:
  MecanumOdometryParams params_;
  Pose2 pose_;
};

/// Ackermann geometry: base_link on the rear axle. Defaults: the capstone delivery robot.
struct AckermannOdometryParams {
  double wheelbase_m = 0.65;
  absl::Status Validate() const;
};

/// Ackermann odometry with the kinematic bicycle model: the rear axle advances by the measured
/// arc length ds and the heading changes by ds·tan(δ)/L for the steering angle δ. Value type.
class AckermannOdometry {
 public:
  explicit AckermannOdometry(const AckermannOdometryParams& params) : params_(params) {}
  BodyIncrement Update(double rear_arc_m, double steering_rad);
  const Pose2& pose_in_odom() const { return pose_; }

 private:
  AckermannOdometryParams params_;
  Pose2 pose_;
};

/// Noise parameters of the odometry EKF. Defaults suit a slow farm robot with a MEMS gyro.
struct OdomEkfParams {
  double accel_noise_mps2 = 0.5;              ///< process noise on linear accelerations
  double yaw_accel_noise_radps2 = 1.0;        ///< process noise on the yaw acceleration
  double wheel_speed_stddev_mps = 0.02;       ///< wheel-odometry body speed (per axis)
  double wheel_yaw_rate_stddev_radps = 0.05;  ///< wheel-odometry yaw rate (slip, track error)
  double gyro_stddev_radps = 0.005;
  double gyro_bias_walk_radps = 1e-4;  ///< random walk of the gyro bias per √s
  absl::Status Validate() const;
};

/// An extended Kalman filter on the odom frame (the role of robot_localization's
/// ekf_localization_node in the Lely thesis §6.5): state [x, y, yaw, v_x, v_y, ω, gyro bias]
/// with a constant-velocity model; measurements are the wheel-odometry body twist and the gyro
/// yaw rate. The output is the continuous odom → base_link pose with its 3×3 covariance
/// (REP 105: never jumps). Probabilistic Robotics §3.3. Value type; not thread-safe.
class OdomEkf {
 public:
  explicit OdomEkf(const OdomEkfParams& params);
  /// Propagates the state by dt_s ≥ 0.
  absl::Status Predict(double dt_s);
  /// Fuses a wheel-odometry body twist (v_x, v_y, ω). For a non-holonomic robot pass v_y = 0:
  /// it then acts as the non-holonomic constraint.
  void FuseWheelTwist(const Eigen::Vector3d& twist);
  /// Fuses a gyro yaw rate (rad/s); the filter estimates the gyro's bias.
  void FuseGyro(double yaw_rate_radps);
  Pose2 pose_in_odom() const;
  Eigen::Matrix3d pose_covariance() const { return cov_.topLeftCorner<3, 3>(); }
  Eigen::Vector3d twist() const { return state_.segment<3>(3); }
  double gyro_bias_radps() const { return state_(6); }

 private:
  void Fuse(const Eigen::Matrix<double, Eigen::Dynamic, 7>& h, const Eigen::VectorXd& innovation,
            const Eigen::MatrixXd& noise);

  OdomEkfParams params_;
  Eigen::Matrix<double, 7, 1> state_;
  Eigen::Matrix<double, 7, 7> cov_;
};

}  // namespace fleetnav::localization
