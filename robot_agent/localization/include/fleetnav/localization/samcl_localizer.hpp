#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/angles.hpp"
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
  /// How the ultrasonics are weighed on a robot without a laser. kBeam (default): the beam
  /// model — each particle's expected range is the nearest surface of the map anywhere in the
  /// sensor's cone (ray casting), which is what an ultrasonic reports. kLikelihoodField: the
  /// reading's end point on the cone's axis (the thesis's fake laser), which reads an oblique
  /// echo short — by 6.5 % 40° off a fence's normal — so during a turn in place 2 m from a
  /// fence the estimate was pulled 0.1 m towards it and free legs ended up to 0.15 m off their
  /// goals (generated barn 1025). Robots with a laser always use the likelihood field.
  SensorModelType ultrasonic_sensor_model = SensorModelType::kBeam;
  /// The beam model's mixture for the ultrasonics: BeamModelParams' defaults, σ_hit 0.1 m. At
  /// 5 cm (the likelihood field's) the first echoes past the edge of a fence gap the map does
  /// not show — the cone's far edge finding the fence's end 0.2–0.45 m beyond the mapped fence —
  /// were fitted whole by particles that far from it: the estimate moved 0.3 m off in 2 s, the
  /// fence's echoes after the gap then lay more than unmapped_obstacle_margin_m short of the
  /// estimate's and were left out as unmapped, and the robot touched the fence (generated
  /// error-case barn 1156, seed 2).
  BeamModelParams ultrasonic_beam;
  /// Opening angle of the ultrasonics' cone (RangeBeam::cone_rad): the PIL P42's 10° (thesis
  /// §4.3.1), as the simulator models it. Meant for the beam model, where the cone's nearest
  /// surface is the expected range. With the likelihood field a cone is scored by the best of its
  /// rays, which fits wrong poses too (an estimate started 45° off stayed plausible and was
  /// never declared lost), so use 0 there.
  double ultrasonic_cone_rad = DegToRad(10.0);
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
/// ultrasonics (§5.3), weighed by the beam model over each sensor's cone, or a 2D laser against
/// the map's likelihood field — correct AMCL; a rising
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
