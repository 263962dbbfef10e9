#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/core/sensor_frame.hpp"

namespace fleetnav::localization {

/// Where a localizer believes the robot is after its last update (REP 105 frames).
struct LocalizerEstimate {
  Pose2 pose_in_map;
  Pose2 pose_in_odom;                                    ///< continuous odometry pose: never jumps
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  ///< of pose_in_map (x, y, yaw)
  Twist2 velocity;                                       ///< body frame, from odometry
  /// In [0, 1]: how far the estimate can be trusted (filter spread and measurement fit).
  double confidence = 0.0;
  /// The estimate has diverged: the robot must stop.
  bool lost = false;
  std::string lost_reason;  ///< why, for people (empty while not lost)
  /// Path length driven (m), forward and backward both counted positive.
  double distance_travelled_m = 0.0;
  int64_t stamp_ns = 0;
};

/// A calibration the localizer applied on a stripe marker (Lely thesis §5.4).
struct MarkerCalibration {
  int marker_id = -1;
  std::string sensor_name;
  int64_t stamp_ns = 0;
  double correction_m = 0.0;  ///< how far the estimate moved
  Pose2 pose_in_map;          ///< the estimate after the correction
  /// false: the marker was recognised but not used (plain AMCL, the SAMCL baseline).
  bool applied = true;
};

/// The robot's localization as the agent's control loop sees it: one Update per control tick
/// with that tick's sensor frame, then an estimate of the pose in map. Implementations: dead
/// reckoning (odometry + gyro EKF) and SAMCL (the same EKF as motion model, AMCL on the fake
/// laser, stripe-marker calibration). Not thread-safe; one instance per robot.
class Localizer {
 public:
  virtual ~Localizer() = default;
  /// Consumes one tick's frame (the first frame only latches the encoders).
  virtual absl::Status Update(const SensorFrame& frame) = 0;
  virtual const LocalizerEstimate& estimate() const = 0;
  /// The marker calibrations applied since the last call.
  virtual std::vector<MarkerCalibration> TakeCalibrations() = 0;
};

}  // namespace fleetnav::localization
