#pragma once

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"

namespace fleetnav::agent {

/// Gains of the polar move-to-pose law. Locally exponentially stable for k_rho > 0,
/// k_beta < 0 and k_alpha > k_rho; the robot never turns the goal behind it on the way when
/// also k_alpha + 5/3 k_beta − 2/π k_rho > 0 (Siegwart, Nourbakhsh & Scaramuzza §3.6.2.4).
/// The heading converges more slowly than the distance (the angles' slow eigenvalue, here
/// 0.59 / s, is below k_rho): these gains keep the heading error at arrival small
/// (∝ ρ^0.59; the textbook's 3 / 8 / −1.5 give ∝ ρ^0.39).
struct PolarPoseGains {
  double k_rho_per_s = 1.0;
  double k_alpha_per_s = 5.0;
  double k_beta_per_s = -2.0;
  absl::Status Validate() const;
};

/// One step of the law: the speed (negative when the robot backs onto the goal) and the
/// curvature ω / v to drive, and the polar coordinates they came from.
struct PolarPoseCommand {
  double speed_mps = 0.0;
  double curvature_per_m = 0.0;
  double distance_m = 0.0;  ///< ρ
  double alpha_rad = 0.0;   ///< the goal's bearing off the direction of travel
  double beta_rad = 0.0;    ///< the goal heading's angle to the line of sight
};

/// The polar move-to-pose law (Astolfi 1999; Siegwart et al., "Introduction to Autonomous
/// Mobile Robots", §3.6.2.4), as the Ashesi capstone drives its Ackermann robot to a pose: in
/// polar coordinates of the goal frame, ρ the distance, α the bearing of the goal off the
/// heading, β = −θ − α, the unicycle law v = k_ρ ρ, ω = k_α α + k_β β; a car drives the
/// curvature ω / v, which its caller bounds by the steering lock. With `reverse` the robot backs
/// onto the goal (the law applied with both headings turned round). Pure function.
PolarPoseCommand PolarMoveToPose(const Pose2& pose, const Pose2& goal, const PolarPoseGains& gains,
                                 bool reverse);

}  // namespace fleetnav::agent
