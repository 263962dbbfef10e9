#include "fleetnav/localization/dead_reckoning_localizer.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace fleetnav::localization {

void FillOdometry(const OdometryFrontEnd& odometry, int64_t stamp_ns, LocalizerEstimate* out) {
  out->pose_in_odom = odometry.pose_in_odom();
  out->velocity = odometry.velocity();
  out->distance_travelled_m = odometry.distance_travelled_m();
  out->stamp_ns = stamp_ns;
}

absl::StatusOr<DeadReckoningLocalizer> DeadReckoningLocalizer::Create(
    const RobotModel& model, const Pose2& start_in_map, const OdometryFrontEndParams& params,
    double confidence_stddev_m) {
  if (!start_in_map.IsFinite()) return absl::InvalidArgumentError("start_in_map: not finite");
  if (!(std::isfinite(confidence_stddev_m) && confidence_stddev_m > 0.0)) {
    return absl::InvalidArgumentError("confidence_stddev_m: must be finite and > 0");
  }
  absl::StatusOr<OdometryFrontEnd> odometry = OdometryFrontEnd::Create(model, params);
  if (!odometry.ok()) return odometry.status();
  return DeadReckoningLocalizer(*std::move(odometry), start_in_map, confidence_stddev_m);
}

DeadReckoningLocalizer::DeadReckoningLocalizer(OdometryFrontEnd odometry, const Pose2& start_in_map,
                                               double confidence_stddev_m)
    : odometry_(std::move(odometry)),
      start_in_map_(start_in_map),
      confidence_stddev_m_(confidence_stddev_m) {
  estimate_.pose_in_map = start_in_map;
  estimate_.confidence = 1.0;
}

absl::Status DeadReckoningLocalizer::Update(const SensorFrame& frame) {
  if (absl::Status s = odometry_.Update(frame); !s.ok()) return s;
  FillOdometry(odometry_, frame.stamp_ns, &estimate_);
  estimate_.pose_in_map = start_in_map_ * estimate_.pose_in_odom;
  const Eigen::Matrix3d odom_cov = odometry_.covariance();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  rotation.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(start_in_map_.yaw_rad()).toRotationMatrix();
  estimate_.covariance = rotation * odom_cov * rotation.transpose();
  const double spread_m =
      std::sqrt(std::max(0.0, estimate_.covariance(0, 0) + estimate_.covariance(1, 1)));
  estimate_.confidence = std::exp(-spread_m / confidence_stddev_m_);
  estimate_.lost = false;
  return absl::OkStatus();
}

}  // namespace fleetnav::localization
