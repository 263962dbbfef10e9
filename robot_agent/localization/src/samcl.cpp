#include "fleetnav/localization/samcl.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"

namespace fleetnav::localization {

absl::Status SamclParams::Validate() const {
  if (!(std::isfinite(association_radius_m) && association_radius_m > 0.0)) {
    return absl::InvalidArgumentError("association_radius_m must be finite and > 0");
  }
  if (!(std::isfinite(soft_sigma_m) && soft_sigma_m > 0.0)) {
    return absl::InvalidArgumentError("soft_sigma_m must be finite and > 0");
  }
  if (!(std::isfinite(marker_half_width_m) && marker_half_width_m >= 0.0)) {
    return absl::InvalidArgumentError("marker_half_width_m must be finite and >= 0");
  }
  if (!(min_crossing_angle_rad >= 0.0 && min_crossing_angle_rad <= kPi / 2.0)) {
    return absl::InvalidArgumentError("min_crossing_angle_rad must be in [0, pi/2]");
  }
  if (!(std::isfinite(odometry_history_s) && odometry_history_s > 0.0)) {
    return absl::InvalidArgumentError("odometry_history_s must be finite and > 0");
  }
  if (!(std::isfinite(far_association_radius_m) && far_association_radius_m >= 0.0)) {
    return absl::InvalidArgumentError("far_association_radius_m must be finite and >= 0");
  }
  if (!(std::isfinite(feature_sigma_m) && feature_sigma_m > 0.0)) {
    return absl::InvalidArgumentError("feature_sigma_m must be finite and > 0");
  }
  if (!(std::isfinite(decisive_mahalanobis2) && decisive_mahalanobis2 >= 0.0)) {
    return absl::InvalidArgumentError("decisive_mahalanobis2 must be finite and >= 0");
  }
  if (!(std::isfinite(edge_memory_m) && edge_memory_m >= 0.0)) {
    return absl::InvalidArgumentError("edge_memory_m must be finite and >= 0");
  }
  return absl::OkStatus();
}

namespace {

/// The point of a marker's or stripe piece's strip nearest to `p`.
Eigen::Vector2d NearestOnStrip(const StripeMarker& m, const Eigen::Vector2d& p) {
  const Line2 line = m.AsLine();
  const double t =
      std::clamp((p - line.point).dot(line.direction), -0.5 * m.length_m, 0.5 * m.length_m);
  return line.point + t * line.direction;
}

/// Where a sensor moving from `p` along `heading` meets a stripe piece: where its path crosses
/// the piece (clamped to the piece's ends), or, for a piece that runs along the path, at the end
/// the path reaches first — a piece the sensor runs beside is felt nowhere along it.
Eigen::Vector2d EntryPoint(const StripeMarker& m, const Eigen::Vector2d& p,
                           const Eigen::Vector2d& heading) {
  const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
  };
  const Line2 line = m.AsLine();
  const double half_m = 0.5 * m.length_m;
  constexpr double kAlongPathSin = 0.26;  // within 15 deg of the path
  const double sin_angle = cross(line.direction, heading);
  if (std::abs(sin_angle) > kAlongPathSin) {
    const double t = cross(p - line.point, heading) / sin_angle;
    return line.point + std::clamp(t, -half_m, half_m) * line.direction;
  }
  const Eigen::Vector2d a = line.point - half_m * line.direction;
  const Eigen::Vector2d b = line.point + half_m * line.direction;
  return (a - p).dot(heading) < (b - p).dot(heading) ? a : b;
}

}  // namespace

const StripeMarker* Samcl::RivalStripe(const StripeMarker& marker, const SensorMount& mount,
                                       const std::string& sensor_name,
                                       const Pose2& odom_at_edge) const {
  const Pose2 robot = amcl_.PoseInMap(odom_at_edge);
  const Eigen::Vector2d s_in_base = mount.pose_in_base.translation();
  const Eigen::Vector2d sensor = robot.TransformPoint(s_in_base);
  const Eigen::Vector2d heading(std::cos(robot.yaw_rad()), std::sin(robot.yaw_rad()));
  // The estimate's covariance carried to the sensor point: p = t + R(yaw)·s.
  const double c = heading.x(), sn = heading.y();
  Eigen::Matrix<double, 2, 3> jacobian;
  jacobian << 1.0, 0.0, -sn * s_in_base.x() - c * s_in_base.y(),  //
      0.0, 1.0, c * s_in_base.x() - sn * s_in_base.y();
  const Eigen::Matrix2d spread =
      jacobian * amcl_.estimate().covariance * jacobian.transpose() +
      params_.feature_sigma_m * params_.feature_sigma_m * Eigen::Matrix2d::Identity();
  const Eigen::Matrix2d information = spread.inverse();
  const auto mahalanobis2 = [&](const Eigen::Vector2d& d) { return d.dot(information * d); };

  const Eigen::Vector2d to_marker = NearestOnStrip(marker, sensor) - sensor;
  const double marker_m2 = mahalanobis2(to_marker);
  // Where this sensor's previous edge was, seen through the current estimate: if this edge is
  // the marker, that point moves with the same correction.
  constexpr double kFeltAgainM = 0.1;
  const auto on_piece = [&](const StripeMarker& m, const Eigen::Vector2d& point) {
    return (NearestOnStrip(m, point) - point).norm() < kFeltAgainM;
  };
  std::optional<Eigen::Vector2d> previous_edge;
  // The pieces the previous edge lies on as it stands: a piece other than the rival there
  // explains it, and then it says nothing about this edge (stripe 2 crossed 0.74 m before
  // stripe 4's end, which lay 0.73 m before the marker: shifted by the marker's correction,
  // stripe 2's edge fell on stripe 4).
  std::vector<const StripeMarker*> previous_pieces;
  if (auto it = last_edge_odom_.find(sensor_name); it != last_edge_odom_.end()) {
    const Pose2& odom_then = it->second;
    const double travelled_m =
        std::hypot(odom_at_edge.x_m() - odom_then.x_m(), odom_at_edge.y_m() - odom_then.y_m());
    if (travelled_m <= params_.edge_memory_m) {
      const Eigen::Vector2d uncorrected = amcl_.PoseInMap(odom_then).TransformPoint(s_in_base);
      previous_edge = uncorrected + to_marker;
      for (const StripeMarker& n : markers_.markers) {
        if (n.kind != MarkerKind::kCalibration && on_piece(n, uncorrected)) {
          previous_pieces.push_back(&n);
        }
      }
    }
  }
  const auto explained_elsewhere = [&](const StripeMarker& piece) {
    return std::any_of(previous_pieces.begin(), previous_pieces.end(),
                       [&](const StripeMarker* n) { return n != &piece; });
  };
  for (const StripeMarker& m : markers_.markers) {
    if (m.kind == MarkerKind::kCalibration) continue;
    const Eigen::Vector2d to_piece = EntryPoint(m, sensor, heading) - sensor;
    if (to_piece.norm() >= params_.association_radius_m) continue;
    if (mahalanobis2(to_piece) >= marker_m2 + params_.decisive_mahalanobis2) continue;
    // This edge is the marker and the previous one was this piece, felt again.
    if (previous_edge && on_piece(m, *previous_edge) && !explained_elsewhere(m)) continue;
    return &m;
  }
  return nullptr;
}

const StripeMarker* Samcl::FarMarker(const Eigen::Vector2d& sensor_estimate,
                                     const Eigen::Vector2d& heading) const {
  const StripeMarker* nearest = nullptr;
  double nearest_m = std::numeric_limits<double>::infinity();
  double second_m = std::numeric_limits<double>::infinity();
  for (const StripeMarker& m : markers_.markers) {
    const Eigen::Vector2d along(std::cos(m.yaw_rad), std::sin(m.yaw_rad));
    const bool crosses_travel =
        std::abs(heading.dot(along)) <= std::cos(params_.min_crossing_angle_rad);
    if (m.kind != MarkerKind::kCalibration) {
      // A stripe crossed nearby may be what the sensor felt: then nothing is associated.
      const double distance_m = (NearestOnStrip(m, sensor_estimate) - sensor_estimate).norm();
      if (crosses_travel && distance_m < params_.far_association_radius_m) return nullptr;
      continue;
    }
    if (!crosses_travel) continue;
    const double distance_m = (m.position_m - sensor_estimate).norm();
    if (distance_m < nearest_m) {
      second_m = nearest_m;
      nearest_m = distance_m;
      nearest = &m;
    } else {
      second_m = std::min(second_m, distance_m);
    }
  }
  if (nearest == nullptr || nearest_m >= params_.far_association_radius_m ||
      second_m < 2.0 * nearest_m) {
    return nullptr;
  }
  return nearest;
}

absl::StatusOr<Samcl> Samcl::Create(Amcl amcl, MarkerSet markers, RobotModel model,
                                    const SamclParams& params) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (absl::Status s = markers.Validate(); !s.ok()) return s;
  return Samcl(std::move(amcl), std::move(markers), std::move(model), params);
}

void Samcl::RecordOdometry(const Pose2& pose_in_odom, int64_t stamp_ns) {
  if (!odometry_.empty() && stamp_ns <= odometry_.back().first) return;
  odometry_.emplace_back(stamp_ns, pose_in_odom);
  const int64_t horizon = static_cast<int64_t>(params_.odometry_history_s * 1e9);
  while (odometry_.size() > 2 && odometry_.front().first < stamp_ns - horizon) {
    odometry_.pop_front();
  }
}

absl::StatusOr<bool> Samcl::Update(const Pose2& pose_in_odom, const RangeObservation& observation,
                                   int64_t stamp_ns) {
  RecordOdometry(pose_in_odom, stamp_ns);
  return amcl_.Update(pose_in_odom, observation, stamp_ns);
}

absl::StatusOr<Pose2> Samcl::OdometryAt(int64_t stamp_ns) const {
  if (odometry_.empty() || stamp_ns < odometry_.front().first ||
      stamp_ns > odometry_.back().first) {
    return absl::OutOfRangeError(absl::StrCat("no odometry around stamp ", stamp_ns));
  }
  for (size_t i = 1; i < odometry_.size(); ++i) {
    const auto& [t1, p1] = odometry_[i];
    if (stamp_ns > t1) continue;
    const auto& [t0, p0] = odometry_[i - 1];
    const double a = static_cast<double>(stamp_ns - t0) / static_cast<double>(t1 - t0);
    return Pose2(p0.x_m() + a * (p1.x_m() - p0.x_m()), p0.y_m() + a * (p1.y_m() - p0.y_m()),
                 p0.yaw_rad() + a * AngleDifference(p1.yaw_rad(), p0.yaw_rad()));
  }
  return odometry_.back().second;
}

absl::StatusOr<CalibrationResult> Samcl::OnInductiveEdge(const InductiveEdge& edge) {
  if (!amcl_.initialized()) return absl::FailedPreconditionError("AMCL is not initialized");
  const SensorMount* mount = model_.FindSensor(edge.sensor_name);
  if (mount == nullptr || mount->type != SensorType::kInductive) {
    return absl::InvalidArgumentError(
        absl::StrCat("'", edge.sensor_name, "' is not an inductive sensor of ", model_.kind_name));
  }
  absl::StatusOr<Pose2> odom_at_edge = OdometryAt(edge.stamp_ns);
  if (!odom_at_edge.ok()) return odom_at_edge.status();
  const Pose2 odom_now = odometry_.back().second;
  // Bring the particles to "now", then look at them at the edge through the odometry delta.
  if (absl::Status s = amcl_.Predict(odom_now); !s.ok()) return s;
  const Pose2 back = Between(odom_now, *odom_at_edge);  // edge pose seen from now

  // 1. Determine the marker (Algorithm 4, lines 21–24), refusing ambiguity.
  const Pose2 estimate_at_edge = amcl_.PoseInMap(*odom_at_edge);
  const Eigen::Vector2d sensor_estimate =
      estimate_at_edge.TransformPoint(mount->pose_in_base.translation());
  CalibrationResult result;
  const StripeMarker* marker = nullptr;
  int candidates = 0;
  const Eigen::Vector2d heading(std::cos(estimate_at_edge.yaw_rad()),
                                std::sin(estimate_at_edge.yaw_rad()));
  for (const StripeMarker& m : markers_.markers) {
    if (m.kind != MarkerKind::kCalibration) continue;
    // A marker is crossed, not driven along: metal met while heading along the marker's line
    // (a stripe crossed near it) is not that marker.
    const Eigen::Vector2d along(std::cos(m.yaw_rad), std::sin(m.yaw_rad));
    if (std::abs(heading.dot(along)) > std::cos(params_.min_crossing_angle_rad)) continue;
    if ((m.position_m - sensor_estimate).norm() < params_.association_radius_m) {
      marker = &m;
      ++candidates;
    }
  }
  if (candidates == 0 && params_.far_association_radius_m > params_.association_radius_m) {
    marker = FarMarker(sensor_estimate, heading);
    if (marker != nullptr) candidates = 1;
  }
  const StripeMarker* rival =
      candidates == 1 ? RivalStripe(*marker, *mount, edge.sensor_name, *odom_at_edge) : nullptr;
  // Whatever this edge turns out to be, the sensor's next edge looks back to it.
  last_edge_odom_[edge.sensor_name] = *odom_at_edge;
  if (candidates == 0) return result;
  if (candidates > 1) {
    result.outcome = CalibrationOutcome::kAmbiguous;
    return result;
  }
  if (rival != nullptr) {
    result.outcome = CalibrationOutcome::kStripe;
    return result;
  }
  result.marker_id = marker->id;
  result.outcome = CalibrationOutcome::kApplied;
  const Line2 line = marker->AsLine();
  const Eigen::Vector2d normal(-line.direction.y(), line.direction.x());

  // 2–3. Per particle: its sensor point at the edge, its foot point, and the shift between.
  ParticleSet& p = amcl_.mutable_particles();
  const double bx = back.x_m(), by = back.y_m(), byaw = back.yaw_rad();
  const Eigen::Vector2d s_in_base = mount->pose_in_base.translation();
  double shift_sum = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    const double yaw = p.yaw_rad[i];
    const double c = std::cos(yaw), s = std::sin(yaw);
    const double ex = p.x_m[i] + c * bx - s * by;
    const double ey = p.y_m[i] + s * bx + c * by;
    const double eyaw = yaw + byaw;
    const double ec = std::cos(eyaw), es = std::sin(eyaw);
    const Eigen::Vector2d sensor(ex + ec * s_in_base.x() - es * s_in_base.y(),
                                 ey + es * s_in_base.x() + ec * s_in_base.y());
    // The sensor first meets the marker's near edge, half its width before its centre line.
    const double approach = (ec * normal.x() + es * normal.y()) >= 0.0 ? 1.0 : -1.0;
    const double signed_distance =
        (sensor - line.point).dot(normal) + approach * params_.marker_half_width_m;
    if (params_.mode == SamclMode::kHard) {
      // The foot point is sensor − d·n: shift the particle by the same vector.
      p.x_m[i] -= static_cast<float>(signed_distance * normal.x());
      p.y_m[i] -= static_cast<float>(signed_distance * normal.y());
      shift_sum += std::abs(signed_distance) * p.weight[i];
    } else {
      const double z = signed_distance / params_.soft_sigma_m;
      p.weight[i] *= std::exp(-0.5 * z * z);
    }
  }
  const Pose2 before = amcl_.estimate().pose_in_map;
  if (params_.mode == SamclMode::kSoft) {
    double total = 0.0;
    for (double w : p.weight) total += w;
    if (total > 0.0 && std::isfinite(total)) {
      for (double& w : p.weight) w /= total;
    } else {
      p.SetUniformWeights();
    }
    amcl_.Resample();
  }
  amcl_.RecomputeEstimate(odometry_.back().first);
  result.correction_m =
      params_.mode == SamclMode::kHard
          ? shift_sum
          : (amcl_.estimate().pose_in_map.translation() - before.translation()).norm();
  return result;
}

}  // namespace fleetnav::localization
