#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/core/sensor_frame.hpp"
#include "fleetnav/localization/odometry.hpp"

namespace fleetnav::localization {

/// The EKF's noise for the agent: wheel yaw rates are trusted little (a heavy robot's caster
/// and slipping wheels), the gyro much; a consistent disagreement must not become "gyro bias".
OdomEkfParams DefaultFrontEndEkfParams();

struct OdometryFrontEndParams {
  OdomEkfParams ekf = DefaultFrontEndEkfParams();
  /// Zero-velocity update: when no wheel has moved for this long the robot is standing, the
  /// gyro is not integrated (its bias would turn a parked robot) and the EKF sees a zero twist.
  double standstill_after_s = 0.2;
  /// Ackermann robots: the yaw from the measured steering angle (bicycle model) instead of the
  /// rear wheels' difference, when the frame has one. The gyro, trusted more by the EKF, takes
  /// up most of the bicycle model's over-reading where the tyres slip through a turn.
  bool ackermann_yaw_from_steering = true;
  absl::Status Validate() const;
};

/// The odometry of the robot's kinematics from its wheel encoders, fused with the gyro in the
/// odometry EKF (Lely thesis §6.5; robot_localization's role). Differential drives and the
/// Ackermann robot's rear wheels use eq. 3.1–3.4 ("left", "right") — with
/// `ackermann_yaw_from_steering` (the default), the Ackermann robot's yaw from its measured
/// steering angle instead when the frame has one (AckermannOdometry, the bicycle model: the rear
/// axle's arc times tan δ / L) —; the mecanum platform uses the KUKA thesis's forward kinematics
/// over "front_left", "front_right", "rear_left", "rear_right". The pose in odom is continuous (REP
/// 105). Not thread-safe.
class OdometryFrontEnd {
 public:
  /// InvalidArgument when the model's wheel geometry is unusable.
  static absl::StatusOr<OdometryFrontEnd> Create(const RobotModel& model,
                                                 const OdometryFrontEndParams& params);

  /// Consumes one frame. The first frame only latches the encoders. InvalidArgument names a
  /// wheel encoder the kinematics needs and the frame lacks.
  absl::Status Update(const SensorFrame& frame);

  Pose2 pose_in_odom() const { return ekf_.pose_in_odom(); }
  Eigen::Matrix3d covariance() const { return ekf_.pose_covariance(); }
  /// Body twist (v_x, v_y, ω) estimated by the EKF.
  Twist2 velocity() const;
  /// Twist measured by the wheels alone over the last frame (for stall detection).
  const Twist2& wheel_velocity() const { return wheel_velocity_; }
  double distance_travelled_m() const { return distance_m_; }
  bool standing_still() const { return still_s_ >= params_.standstill_after_s; }
  double gyro_bias_radps() const { return ekf_.gyro_bias_radps(); }

 private:
  OdometryFrontEnd(const RobotModel& model, const OdometryFrontEndParams& params);

  RobotModel model_;
  OdometryFrontEndParams params_;
  OdomEkf ekf_;
  DiffDriveOdometry diff_;
  MecanumOdometry mecanum_;
  AckermannOdometry ackermann_;
  std::map<std::string, int64_t> last_ticks_;
  std::optional<int64_t> last_stamp_ns_;
  Twist2 wheel_velocity_;
  double distance_m_ = 0.0;
  double still_s_ = 0.0;
};

}  // namespace fleetnav::localization
