#include "fleetnav/localization/samcl_localizer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/localization/dead_reckoning_localizer.hpp"

namespace fleetnav::localization {
namespace {

/// A sensor whose lateral reading puts the stripe this close is over that stripe (5 cm wide).
constexpr double kOnStripeM = 0.035;

}  // namespace

AmclParams DefaultAgentAmclParams() {
  AmclParams p;
  p.min_particles = 500;
  p.max_particles = 2000;
  // The motion model's input is the gyro-aided EKF: its heading is far better than wheel
  // odometry's, so rotation noise is small (a loose yaw would random-walk where two
  // ultrasonic beams cannot observe it).
  p.motion.alpha1 = 0.005;
  p.motion.alpha2 = 0.0001;
  p.motion.alpha3 = 0.001;
  p.motion.alpha4 = 0.001;
  p.likelihood_field.sigma_hit_m = 0.05;
  p.update_min_distance_m = 0.05;
  p.update_min_angle_rad = DegToRad(3.0);
  // Two ultrasonic beams cannot tell a kidnapping from a fence gap: random particles would
  // carry the estimate off to some other fence. The robot's start is known; tracking only.
  p.max_injection_fraction = 0.0;
  // Lost means diverged: the cloud spread over half a metre, or measurements that the map
  // cannot explain for 40 updates in a row (2 m of travel, or two turns in place) — not a few
  // oblique echoes of two ultrasonics while turning.
  p.lost_position_stddev_m = 0.5;
  p.lost_likelihood_score = 0.05;
  p.lost_min_updates = 40;
  // The small motion noise above makes the cloud a few centimetres wide: where the ranges stop
  // fitting (an along-track error turned across by a turn), jitter it so it can move.
  p.roughening_stddev_m = 0.02;
  p.roughening_stddev_rad = DegToRad(0.3);
  p.roughening_below_score = 0.3;
  return p;
}

absl::Status SamclLocalizerParams::Validate() const {
  if (absl::Status s = amcl.Validate(); !s.ok()) return s;
  if (absl::Status s = samcl.Validate(); !s.ok()) return s;
  if (absl::Status s = odometry.Validate(); !s.ok()) return s;
  if (absl::Status s = ultrasonic_beam.Validate(); !s.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("ultrasonic_beam: ", s.message()));
  }
  if (!(std::isfinite(ultrasonic_range_max_m) && ultrasonic_range_max_m > 0.0)) {
    return absl::InvalidArgumentError("ultrasonic_range_max_m: must be finite and > 0");
  }
  if (!(std::isfinite(ultrasonic_cone_rad) && ultrasonic_cone_rad >= 0.0 &&
        ultrasonic_cone_rad < kPi)) {
    return absl::InvalidArgumentError("ultrasonic_cone_rad: must be in [0, pi)");
  }
  if (laser_max_beams < 0) return absl::InvalidArgumentError("laser_max_beams: must be >= 0");
  if (!(std::isfinite(unmapped_obstacle_margin_m) && unmapped_obstacle_margin_m >= 0.0)) {
    return absl::InvalidArgumentError("unmapped_obstacle_margin_m: must be finite and >= 0");
  }
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
  AmclParams amcl_params = params.amcl;
  const bool has_laser =
      std::any_of(model.sensors.begin(), model.sensors.end(),
                  [](const SensorMount& m) { return m.type == SensorType::kLaser; });
  if (!has_laser && params.ultrasonic_sensor_model == SensorModelType::kBeam) {
    amcl_params.sensor_model = SensorModelType::kBeam;
    amcl_params.beam = params.ultrasonic_beam;
  }
  absl::StatusOr<Amcl> amcl = Amcl::Create(amcl_params, map);
  if (!amcl.ok()) return amcl.status();
  std::vector<Line2> stripes;
  std::vector<StripeMarker> calibration_markers;
  for (const StripeMarker& m : markers.markers) {
    if (m.kind == MarkerKind::kCalibration) {
      calibration_markers.push_back(m);
      continue;
    }
    const Eigen::Vector2d direction(std::cos(m.yaw_rad), std::sin(m.yaw_rad));
    stripes.push_back(Line2{m.position_m - 0.5 * m.length_m * direction, direction * m.length_m});
  }
  absl::StatusOr<Samcl> samcl =
      Samcl::Create(*std::move(amcl), std::move(markers), model, params.samcl);
  if (!samcl.ok()) return samcl.status();
  return SamclLocalizer(model, std::make_shared<const OccupancyGrid>(map), *std::move(odometry),
                        *std::move(samcl), std::move(stripes), std::move(calibration_markers),
                        start_in_map, params);
}

SamclLocalizer::SamclLocalizer(const RobotModel& model, std::shared_ptr<const OccupancyGrid> map,
                               OdometryFrontEnd odometry, Samcl samcl,
                               std::vector<Line2> stripe_pieces,
                               std::vector<StripeMarker> calibration_markers,
                               const Pose2& start_in_map, const SamclLocalizerParams& params)
    : model_(model),
      map_(std::move(map)),
      odometry_(std::move(odometry)),
      samcl_(std::move(samcl)),
      markers_(std::move(calibration_markers)),
      start_in_map_(start_in_map),
      params_(params) {
  // Line2's direction is unit length: keep each piece's length beside it.
  for (Line2& piece : stripe_pieces) {
    const double length = piece.direction.norm();
    piece.direction /= length;
    stripes_.push_back(piece);
    stripe_lengths_m_.push_back(length);
  }
  estimate_.pose_in_map = start_in_map;
}

absl::StatusOr<bool> SamclLocalizer::WeighByStripes(const SensorFrame& frame, const Pose2& odom) {
  if (stripes_.empty() || params_.stripe_sigma_m <= 0.0) return false;
  if (distance_at_stripe_update_m_ >= 0.0 &&
      estimate_.distance_travelled_m - distance_at_stripe_update_m_ <
          params_.stripe_update_distance_m) {
    return false;
  }
  // The readings as points in base_link.
  std::vector<Eigen::Vector2d> readings;
  for (const InductiveSample& sample : frame.inductive) {
    if (!sample.lateral_offset_m) continue;
    const SensorMount* mount = model_.FindSensor(sample.name);
    if (mount == nullptr) continue;
    readings.push_back(
        (mount->pose_in_base * Pose2(0.0, *sample.lateral_offset_m, 0.0)).translation());
  }
  if (readings.empty()) return false;
  Amcl& amcl = samcl_.amcl();
  if (absl::Status s = amcl.Predict(odom); !s.ok()) return s;
  ParticleSet& p = amcl.mutable_particles();
  // Only the distance across a stripe is evidence: where along it the sensor is cannot be told
  // from a stripe reading. Near a piece's ends a reading says nothing (a particle behind the
  // stripe's start would be punished for being there, and the cloud would ratchet forward).
  const auto nearest_stripe_m = [&](const Eigen::Vector2d& point) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < stripes_.size(); ++k) {
      const Eigen::Vector2d d = point - stripes_[k].point;
      const double along = d.dot(stripes_[k].direction);
      if (along < params_.stripe_association_m ||
          along > stripe_lengths_m_[k] - params_.stripe_association_m) {
        continue;
      }
      const Eigen::Vector2d normal(-stripes_[k].direction.y(), stripes_[k].direction.x());
      best = std::min(best, std::abs(d.dot(normal)));
    }
    return best;
  };
  std::vector<double> log_weight(p.size(), 0.0);
  double closest = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < p.size(); ++i) {
    const Pose2 particle(p.x_m[i], p.y_m[i], p.yaw_rad[i]);
    for (const Eigen::Vector2d& reading : readings) {
      const double d = std::min(nearest_stripe_m(particle.TransformPoint(reading)),
                                params_.stripe_association_m);
      closest = std::min(closest, d);
      const double z = d / params_.stripe_sigma_m;
      log_weight[i] -= 0.5 * z * z;
    }
  }
  if (closest >= params_.stripe_association_m) return false;  // a stripe the map lacks
  const double max_log = *std::max_element(log_weight.begin(), log_weight.end());
  double total = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    p.weight[i] *= std::exp(log_weight[i] - max_log);
    total += p.weight[i];
  }
  if (!(total > 0.0 && std::isfinite(total))) {
    p.SetUniformWeights();
  } else {
    for (double& w : p.weight) w /= total;
  }
  if (EffectiveSampleSize(p.weight) < amcl.params().resample_neff_ratio * p.size()) {
    amcl.Resample();
  }
  amcl.RecomputeEstimate(frame.stamp_ns);
  distance_at_stripe_update_m_ = estimate_.distance_travelled_m;
  return true;
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
      RangeObservation one =
          ObservationFromLaser(scan, mount->pose_in_base, params_.laser_max_beams);
      all.beams.insert(all.beams.end(), one.beams.begin(), one.beams.end());
    }
    return all;
  }
  absl::StatusOr<RangeObservation> fake = FakeLaserFromUltrasonics(
      frame.ultrasonic, model_, params_.ultrasonic_range_max_m, params_.ultrasonic_cone_rad);
  if (!fake.ok() || params_.ultrasonic_no_echo_is_evidence) return fake;
  // An ultrasonic is silent for many reasons besides free space (a surface met at more than
  // 40 deg, a soft target, a dropout): as in the thesis (eq. 5.2, 5.4) a silent sensor says
  // nothing.
  RangeObservation echoes;
  for (const RangeBeam& beam : fake->beams) {
    if (!beam.no_echo) echoes.beams.push_back(beam);
  }
  return echoes;
}

absl::Status SamclLocalizer::Update(const SensorFrame& frame) {
  if (absl::Status s = odometry_.Update(frame); !s.ok()) return s;
  FillOdometry(odometry_, frame.stamp_ns, &estimate_);
  const Pose2 odom = estimate_.pose_in_odom;
  if (!started_) {
    if (absl::Status s =
            samcl_.amcl().InitializePose(start_in_map_, params_.start_stddev, odom, frame.stamp_ns);
        !s.ok()) {
      return s;
    }
    started_ = true;
  }
  absl::StatusOr<RangeObservation> observation = Observe(frame);
  if (!observation.ok()) return observation.status();
  if (params_.unmapped_obstacle_margin_m > 0.0) {
    const Pose2 estimate = samcl_.amcl().PoseInMap(odom);
    std::erase_if(observation->beams, [&](const RangeBeam& beam) {
      if (beam.no_echo) return false;
      // Cast past the sensor's reach by the margin: an echo where the map holds nothing within
      // reach and the margin beyond it (a robot parked 2.3 m off the track across open floor)
      // is something unmapped, not a reading the map fails to explain.
      // The cone's nearest surface, as the sensor reports it.
      const Eigen::Vector2d origin = estimate.TransformPoint(beam.origin_in_base);
      const double reach_m = beam.range_max_m + params_.unmapped_obstacle_margin_m;
      double expected_m = reach_m;
      for (double angle : BeamRayAngles(beam)) {
        expected_m =
            std::min(expected_m, CastRay(*map_, origin, estimate.yaw_rad() + angle, reach_m));
      }
      return beam.range_m < expected_m - params_.unmapped_obstacle_margin_m;
    });
  }
  if (!observation->beams.empty()) {
    if (absl::StatusOr<bool> updated = samcl_.Update(odom, *observation, frame.stamp_ns);
        !updated.ok()) {
      return updated.status();
    }
  } else {
    samcl_.RecordOdometry(odom, frame.stamp_ns);
    const absl::StatusOr<bool> predicted = samcl_.amcl().PredictIfMoved(odom);
    if (!predicted.ok()) return predicted.status();
    // The estimate and its health are recomputed at the next range or stripe update.
  }
  for (const InductiveSample& sample : frame.inductive) {
    bool& last = inductive_last_[sample.name];
    const bool rising = sample.detected && !last;
    last = sample.detected;
    // Metal under a sensor that reads the followed stripe right there is that stripe, not a
    // marker crossed.
    const bool on_followed_stripe =
        sample.lateral_offset_m && std::abs(*sample.lateral_offset_m) < kOnStripeM;
    if (!rising || on_followed_stripe) continue;
    if (!params_.use_markers) {
      // Plain AMCL: note which marker the estimate says was crossed, and use nothing.
      const SensorMount* mount = model_.FindSensor(sample.name);
      const Pose2 estimate = samcl_.amcl().PoseInMap(odom);
      if (mount == nullptr) continue;
      const Eigen::Vector2d point = estimate.TransformPoint(mount->pose_in_base.translation());
      for (const StripeMarker& m : markers_) {
        if ((m.position_m - point).norm() < params_.samcl.association_radius_m) {
          calibrations_.push_back(
              {m.id, sample.name, frame.stamp_ns, 0.0, estimate, /*applied=*/false});
          break;
        }
      }
      continue;
    }
    const Pose2 before = samcl_.amcl().PoseInMap(odom);
    absl::StatusOr<CalibrationResult> result =
        samcl_.OnInductiveEdge(InductiveEdge{sample.name, frame.stamp_ns});
    if (!result.ok()) return result.status();
    if (result->outcome != CalibrationOutcome::kApplied) continue;
    const Pose2 after = samcl_.amcl().PoseInMap(odom);
    calibrations_.push_back({result->marker_id, sample.name, frame.stamp_ns,
                             std::hypot(after.x_m() - before.x_m(), after.y_m() - before.y_m()),
                             after, true});
  }
  if (absl::StatusOr<bool> weighed = WeighByStripes(frame, odom); !weighed.ok()) {
    return weighed.status();
  }
  const Amcl& amcl = samcl_.amcl();
  estimate_.pose_in_map = amcl.PoseInMap(odom);
  estimate_.covariance = amcl.estimate().covariance;
  estimate_.confidence = amcl.health().confidence;
  estimate_.lost = amcl.health().lost;
  estimate_.lost_reason = amcl.health().lost_reason;
  return absl::OkStatus();
}

std::vector<MarkerCalibration> SamclLocalizer::TakeCalibrations() {
  return std::exchange(calibrations_, {});
}

}  // namespace fleetnav::localization
