#pragma once

#include <Eigen/Core>
#include <optional>

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/core/zone.hpp"

namespace fleetnav::agent {

/// How the agent keeps to the speed-limit zones of its site (issue 39).
struct ZoneSpeedParams {
  /// The robot counts as where its estimate is, grown by this many standard deviations of the
  /// position (the larger axis of the estimate's covariance) besides its footprint.
  double sigma_multiple = 2.0;
  /// Outside a zone the robot may still drive as fast as lets it slow to the limit by the
  /// zone's edge at this deceleration (m/s²).
  double braking_decel_mps2 = 0.4;
  /// InvalidArgument naming a field that is negative or not finite (deceleration: ≤ 0).
  absl::Status Validate() const;
};

/// How far the robot reaches for zones and stops: `footprint_radius_m` plus `sigma_multiple`
/// standard deviations of its position estimate (the larger axis of the covariance's x-y block;
/// a non-finite covariance counts as certain).
double GrownReachM(const Eigen::Matrix3d& covariance, double footprint_radius_m,
                   const ZoneSpeedParams& params = {});

/// The highest speed (m/s, of base_link) the robot may drive now under the site's speed-limit
/// zones: inside a zone, or within its footprint's circumscribed radius plus the grown
/// uncertainty of one, the zone's limit; farther out, the speed from which it can brake to the
/// limit over the gap left (v = sqrt(limit² + 2·a·gap)). The lowest over all zones; nullopt
/// when there is none.
std::optional<double> ZoneSpeedCap(const ZoneSet& zones, const Pose2& pose_in_map,
                                   const Eigen::Matrix3d& covariance, double footprint_radius_m,
                                   const ZoneSpeedParams& params = {});

/// `command` slowed so that base_link's speed is at most `cap_mps`, its yaw rate scaled alike
/// so that the robot keeps its path's curvature. A command within the cap is returned as is.
Twist2 CapTwist(const Twist2& command, double cap_mps);

}  // namespace fleetnav::agent
