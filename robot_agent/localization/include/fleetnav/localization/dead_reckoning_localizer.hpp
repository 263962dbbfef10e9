#pragma once

#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/localization/localizer.hpp"
#include "fleetnav/localization/odometry_front_end.hpp"

namespace fleetnav::localization {

/// Odometry alone: pose in map = start pose ∘ pose in odom, covariance from the odometry EKF
/// rotated into the map, confidence falling with its spread (1/e at `confidence_stddev_m`).
/// For robots with no map, and as the baseline SAMCL is measured against. Not thread-safe.
class DeadReckoningLocalizer : public Localizer {
 public:
  static absl::StatusOr<DeadReckoningLocalizer> Create(const RobotModel& model,
                                                       const Pose2& start_in_map,
                                                       const OdometryFrontEndParams& params = {},
                                                       double confidence_stddev_m = 0.5);
  absl::Status Update(const SensorFrame& frame) override;
  const LocalizerEstimate& estimate() const override { return estimate_; }
  std::vector<MarkerCalibration> TakeCalibrations() override { return {}; }

 private:
  DeadReckoningLocalizer(OdometryFrontEnd odometry, const Pose2& start_in_map,
                         double confidence_stddev_m);

  OdometryFrontEnd odometry_;
  Pose2 start_in_map_;
  double confidence_stddev_m_;
  LocalizerEstimate estimate_;
};

/// Fills the odometry fields of an estimate (pose in odom, velocity, distance, stamp).
void FillOdometry(const OdometryFrontEnd& odometry, int64_t stamp_ns, LocalizerEstimate* out);

}  // namespace fleetnav::localization
