#pragma once

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/localization/amcl.hpp"
#include "fleetnav/localization/localizer.hpp"
#include "fleetnav/localization/odometry_front_end.hpp"
#include "fleetnav/localization/samcl.hpp"

namespace fleetnav::localization {

/// AMCL settings for a robot's own loop: 2,000 particles at most, odometry noise of a
/// gyro-aided EKF, a sensor update every 5 cm or 3° of motion.
AmclParams DefaultAgentAmclParams();

struct SamclLocalizerParams {
  AmclParams amcl = DefaultAgentAmclParams();
  SamclParams samcl;
  OdometryFrontEndParams odometry;
  /// Range reported by an ultrasonic without echo (the fake laser's range_max).
  double ultrasonic_range_max_m = 2.5;
  /// Laser beams used per update (evenly sub-sampled; 0: all).
  int laser_max_beams = 60;
  /// Spread of the particles around the start pose: a real robot's start is known to a few
  /// centimetres and degrees.
  Eigen::Vector3d start_stddev = Eigen::Vector3d(0.05, 0.05, 0.035);
  /// false: plain AMCL (inductive edges ignored), the baseline of the thesis's Experiment 2.
  bool use_markers = true;
  absl::Status Validate() const;
};

/// SAMCL in the agent's loop (Lely thesis §5.4, Fig. 6.5): every tick the odometry EKF (wheel
/// encoders + gyro) is the motion model; the range sensors — the fake laser of the two
/// ultrasonics (§5.3) or a 2D laser — correct AMCL against the map's likelihood field; a rising
/// edge of an inductive sensor over a calibration marker applies Algorithm 4. The estimate is
/// the best cluster's pose with its weighted covariance; `lost` is AMCL's health verdict.
/// Not thread-safe.
class SamclLocalizer : public Localizer {
 public:
  static absl::StatusOr<SamclLocalizer> Create(const RobotModel& model, const OccupancyGrid& map,
                                               MarkerSet markers, const Pose2& start_in_map,
                                               const SamclLocalizerParams& params = {});
  absl::Status Update(const SensorFrame& frame) override;
  const LocalizerEstimate& estimate() const override { return estimate_; }
  std::vector<MarkerCalibration> TakeCalibrations() override;

  const Amcl& amcl() const { return samcl_.amcl(); }

 private:
  SamclLocalizer(const RobotModel& model, OdometryFrontEnd odometry, Samcl samcl,
                 const Pose2& start_in_map, const SamclLocalizerParams& params);
  absl::StatusOr<RangeObservation> Observe(const SensorFrame& frame) const;

  RobotModel model_;
  OdometryFrontEnd odometry_;
  Samcl samcl_;
  Pose2 start_in_map_;
  SamclLocalizerParams params_;
  bool started_ = false;
  std::map<std::string, bool> inductive_last_;
  std::vector<MarkerCalibration> calibrations_;
  LocalizerEstimate estimate_;
};

}  // namespace fleetnav::localization
