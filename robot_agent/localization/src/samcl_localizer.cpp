#include "fleetnav/localization/samcl_localizer.hpp"

#include <cmath>
#include <utility>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/localization/dead_reckoning_localizer.hpp"

namespace fleetnav::localization {

AmclParams DefaultAgentAmclParams() {
  AmclParams p;
  p.min_particles = 500;
  p.max_particles = 2000;
  p.motion.alpha1 = 0.02;
  p.motion.alpha2 = 0.0005;
  p.motion.alpha3 = 0.002;
  p.motion.alpha4 = 0.002;
  p.likelihood_field.sigma_hit_m = 0.05;
  p.update_min_distance_m = 0.05;
  p.update_min_angle_rad = DegToRad(3.0);
  // Two ultrasonic beams cannot tell a kidnapping from a fence gap: random particles would
  // carry the estimate off to some other fence. The robot's start is known; tracking only.
  p.max_injection_fraction = 0.0;
  return p;
}

absl::Status SamclLocalizerParams::Validate() const {
  if (absl::Status s = amcl.Validate(); !s.ok()) return s;
  if (absl::Status s = samcl.Validate(); !s.ok()) return s;
  if (absl::Status s = odometry.Validate(); !s.ok()) return s;
  if (!(std::isfinite(ultrasonic_range_max_m) && ultrasonic_range_max_m > 0.0)) {
    return absl::InvalidArgumentError("ultrasonic_range_max_m: must be finite and > 0");
  }
  if (laser_max_beams < 0) return absl::InvalidArgumentError("laser_max_beams: must be >= 0");
  if (!start_stddev.allFinite() || (start_stddev.array() < 0.0).any()) {
    return absl::InvalidArgumentError("start_stddev: must be finite and >= 0");
  }
  return absl::OkStatus();
}

absl::StatusOr<SamclLocalizer> SamclLocalizer::Create(const RobotModel& model,
                                                      const OccupancyGrid& map, MarkerSet markers,
                                                      const Pose2& start_in_map,
                                                      const SamclLocalizerParams& params) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (!start_in_map.IsFinite()) return absl::InvalidArgumentError("start_in_map: not finite");
  absl::StatusOr<OdometryFrontEnd> odometry = OdometryFrontEnd::Create(model, params.odometry);
  if (!odometry.ok()) return odometry.status();
  absl::StatusOr<Amcl> amcl = Amcl::Create(params.amcl, map);
  if (!amcl.ok()) return amcl.status();
  absl::StatusOr<Samcl> samcl = Samcl::Create(*std::move(amcl), std::move(markers), model,
                                              params.samcl);
  if (!samcl.ok()) return samcl.status();
  return SamclLocalizer(model, *std::move(odometry), *std::move(samcl), start_in_map, params);
}

SamclLocalizer::SamclLocalizer(const RobotModel& model, OdometryFrontEnd odometry, Samcl samcl,
                               const Pose2& start_in_map, const SamclLocalizerParams& params)
    : model_(model),
      odometry_(std::move(odometry)),
      samcl_(std::move(samcl)),
      start_in_map_(start_in_map),
      params_(params) {
  estimate_.pose_in_map = start_in_map;
}

absl::StatusOr<RangeObservation> SamclLocalizer::Observe(const SensorFrame& frame) const {
  if (!frame.lasers.empty()) {
    RangeObservation all;
    for (const LaserScanSample& scan : frame.lasers) {
      const SensorMount* mount = model_.FindSensor(scan.name);
      if (mount == nullptr) {
        return absl::InvalidArgumentError(
            absl::StrCat("laser '", scan.name, "' is not mounted on ", model_.kind_name));
      }
      RangeObservation one = ObservationFromLaser(scan, mount->pose_in_base, params_.laser_max_beams);
      all.beams.insert(all.beams.end(), one.beams.begin(), one.beams.end());
    }
    return all;
  }
  return FakeLaserFromUltrasonics(frame.ultrasonic, model_, params_.ultrasonic_range_max_m);
}

absl::Status SamclLocalizer::Update(const SensorFrame& frame) {
  if (absl::Status s = odometry_.Update(frame); !s.ok()) return s;
  FillOdometry(odometry_, frame.stamp_ns, &estimate_);
  const Pose2 odom = estimate_.pose_in_odom;
  if (!started_) {
    if (absl::Status s = samcl_.amcl().InitializePose(start_in_map_, params_.start_stddev, odom,
                                                      frame.stamp_ns);
        !s.ok()) {
      return s;
    }
    started_ = true;
  }
  absl::StatusOr<RangeObservation> observation = Observe(frame);
  if (!observation.ok()) return observation.status();
  if (!observation->beams.empty()) {
    if (absl::StatusOr<bool> updated = samcl_.Update(odom, *observation, frame.stamp_ns);
        !updated.ok()) {
      return updated.status();
    }
  } else {
    samcl_.RecordOdometry(odom, frame.stamp_ns);
  }
  for (const InductiveSample& sample : frame.inductive) {
    bool& last = inductive_last_[sample.name];
    const bool rising = sample.detected && !last;
    last = sample.detected;
    if (!rising || !params_.use_markers) continue;
    const Pose2 before = samcl_.amcl().PoseInMap(odom);
    absl::StatusOr<CalibrationResult> result =
        samcl_.OnInductiveEdge(InductiveEdge{sample.name, frame.stamp_ns});
    if (!result.ok()) return result.status();
    if (result->outcome != CalibrationOutcome::kApplied) continue;
    const Pose2 after = samcl_.amcl().PoseInMap(odom);
    calibrations_.push_back(
        {result->marker_id, sample.name, frame.stamp_ns,
         std::hypot(after.x_m() - before.x_m(), after.y_m() - before.y_m())});
  }
  const Amcl& amcl = samcl_.amcl();
  estimate_.pose_in_map = amcl.PoseInMap(odom);
  estimate_.covariance = amcl.estimate().covariance;
  estimate_.confidence = amcl.health().confidence;
  estimate_.lost = amcl.health().lost;
  return absl::OkStatus();
}

std::vector<MarkerCalibration> SamclLocalizer::TakeCalibrations() {
  return std::exchange(calibrations_, {});
}

}  // namespace fleetnav::localization
