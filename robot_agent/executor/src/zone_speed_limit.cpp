#include "fleetnav/robot_agent/zone_speed_limit.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"

namespace fleetnav::agent {

absl::Status ZoneSpeedParams::Validate() const {
  if (!std::isfinite(sigma_multiple) || sigma_multiple < 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("sigma_multiple: must be finite and >= 0, got ", sigma_multiple));
  }
  if (!std::isfinite(braking_decel_mps2) || braking_decel_mps2 <= 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("braking_decel_mps2: must be finite and > 0, got ", braking_decel_mps2));
  }
  return absl::OkStatus();
}

double GrownReachM(const Eigen::Matrix3d& covariance, double footprint_radius_m,
                   const ZoneSpeedParams& params) {
  const Eigen::Matrix2d position = covariance.topLeftCorner<2, 2>();
  const double largest_variance =
      position.allFinite() ? std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(
                                               position, Eigen::EigenvaluesOnly)
                                               .eigenvalues()
                                               .maxCoeff())
                           : 0.0;
  return footprint_radius_m + params.sigma_multiple * std::sqrt(largest_variance);
}

std::optional<double> ZoneSpeedCap(const ZoneSet& zones, const Pose2& pose_in_map,
                                   const Eigen::Matrix3d& covariance, double footprint_radius_m,
                                   const ZoneSpeedParams& params) {
  const double reach_m = GrownReachM(covariance, footprint_radius_m, params);
  const Eigen::Vector2d center = pose_in_map.translation();
  std::optional<double> cap;
  for (const Zone& zone : zones.zones) {
    if (zone.kind != ZoneKind::kSpeedLimit) continue;
    const double gap_m =
        PolygonContains(zone.polygon_in_map, center)
            ? 0.0
            : std::max(0.0, DistanceToPolygonBoundary(zone.polygon_in_map, center) - reach_m);
    const double allowed = std::sqrt(zone.speed_limit_mps * zone.speed_limit_mps +
                                     2.0 * params.braking_decel_mps2 * gap_m);
    cap = std::min(cap.value_or(allowed), allowed);
  }
  return cap;
}

Twist2 CapTwist(const Twist2& command, double cap_mps) {
  const double speed = std::hypot(command.vx_mps, command.vy_mps);
  if (speed <= cap_mps || speed <= 0.0) return command;
  const double scale = std::max(cap_mps, 0.0) / speed;
  return Twist2{command.vx_mps * scale, command.vy_mps * scale, command.yaw_rate_radps * scale};
}

}  // namespace fleetnav::agent
