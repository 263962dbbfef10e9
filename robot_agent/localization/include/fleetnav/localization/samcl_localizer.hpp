#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
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
  /// SAMCL; markers are 5 cm wide strips (the thesis's and the simulator's). A slippery floor
  /// runs odometry a metre and more ahead between markers (a 6 m stretch at 0.9 traction put
  /// the estimate 1.35 m off): an unambiguous marker is still taken up to 2.5 m away.
  SamclParams samcl = [] {
    SamclParams p;
    p.marker_half_width_m = 0.025;
    p.far_association_radius_m = 2.5;
    return p;
  }();
  OdometryFrontEndParams odometry;
  /// Range reported by an ultrasonic without echo (the fake laser's range_max).
  double ultrasonic_range_max_m = 2.5;
  /// Opening angle of the ultrasonics' cone in the sensor model (RangeBeam::cone_rad); 0 (the
  /// default, the thesis's fake laser): each ultrasonic is one ray. With the PIL P42's 10°
  /// (thesis §4.3.1) an echo from 5° off the axis fits where it came from (on the axis alone a
  /// wall met 25° off its normal 2.5 m out reads 8 cm short), but a fan of rays fits wrong
  /// poses too: an estimate started 45° off then stayed plausible on the map and was never
  /// declared lost (ClosedLoop.LostLocalizationStopsTheRobot), so it is off by default.
  double ultrasonic_cone_rad = 0.0;
  /// false (default): an ultrasonic without echo is left out of the update (thesis eq. 5.2).
  bool ultrasonic_no_echo_is_evidence = false;
  /// Laser beams used per update (evenly sub-sampled; 0: all).
  int laser_max_beams = 60;
  /// Spread of the particles around the start pose: a real robot's start is known to a few
  /// centimetres and degrees.
  Eigen::Vector3d start_stddev = Eigen::Vector3d(0.05, 0.05, 0.035);
  /// false: plain AMCL (inductive edges ignored), the baseline of the thesis's Experiment 2.
  bool use_markers = true;
  /// Stripe measurement: while an inductive sensor reads a follow or charger stripe of the
  /// marker set, particles are weighted by how far their view of the reading lies from the
  /// stripe (σ below), every stripe_update_distance_m of travel. 0 disables.
  double stripe_sigma_m = 0.02;
  double stripe_update_distance_m = 0.05;
  /// Readings whose nearest stripe is further than this from every particle are not used.
  double stripe_association_m = 0.3;
  /// A range beam shorter by more than this than the map's range along it from the current
  /// estimate sees something the map does not hold (another robot, a person, a cow) and is
  /// left out of the update, as AMCL's beam skipping does. 0 keeps every beam.
  double unmapped_obstacle_margin_m = 0.5;
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
  SamclLocalizer(const RobotModel& model, std::shared_ptr<const OccupancyGrid> map,
                 OdometryFrontEnd odometry, Samcl samcl, std::vector<Line2> stripe_pieces_start_end,
                 std::vector<StripeMarker> calibration_markers, const Pose2& start_in_map,
                 const SamclLocalizerParams& params);
  absl::StatusOr<RangeObservation> Observe(const SensorFrame& frame) const;
  /// The stripe measurement update (see stripe_sigma_m); returns whether it was applied.
  absl::StatusOr<bool> WeighByStripes(const SensorFrame& frame, const Pose2& odom);

  RobotModel model_;
  std::shared_ptr<const OccupancyGrid> map_;  ///< for unmapped_obstacle_margin_m
  OdometryFrontEnd odometry_;
  Samcl samcl_;
  std::vector<StripeMarker> markers_;  ///< the calibration markers
  Pose2 start_in_map_;
  SamclLocalizerParams params_;
  bool started_ = false;
  std::map<std::string, bool> inductive_last_;
  /// Follow and charger stripe pieces as segments: point = one end, direction·length = the other.
  std::vector<Line2> stripes_;
  std::vector<double> stripe_lengths_m_;
  double distance_at_stripe_update_m_ = -1.0;
  std::vector<MarkerCalibration> calibrations_;
  LocalizerEstimate estimate_;
};

}  // namespace fleetnav::localization
