#include "fleetnav/robot_agent/control/common/polar_pose_control.hpp"

#include <cmath>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {

absl::Status PolarPoseGains::Validate() const {
  if (!(std::isfinite(k_rho_per_s) && std::isfinite(k_alpha_per_s) && std::isfinite(k_beta_per_s) &&
        k_rho_per_s > 0.0 && k_beta_per_s < 0.0 && k_alpha_per_s > k_rho_per_s)) {
    return absl::InvalidArgumentError(
        "polar move-to-pose gains: k_rho > 0, k_beta < 0 and k_alpha > k_rho required");
  }
  return absl::OkStatus();
}

PolarPoseCommand PolarMoveToPose(const Pose2& pose, const Pose2& goal, const PolarPoseGains& gains,
                                 bool reverse) {
  // Backing onto the goal is driving forwards with both headings turned round.
  const Pose2 turn(0.0, 0.0, reverse ? kPi : 0.0);
  const Pose2 robot_in_goal = (goal * turn).Inverse() * (pose * turn);
  PolarPoseCommand out;
  out.distance_m = robot_in_goal.translation().norm();
  if (out.distance_m < 1e-9) return out;
  const double theta = robot_in_goal.yaw_rad();
  out.alpha_rad = NormalizeAngle(std::atan2(-robot_in_goal.y_m(), -robot_in_goal.x_m()) - theta);
  out.beta_rad = NormalizeAngle(-theta - out.alpha_rad);
  const double speed = gains.k_rho_per_s * out.distance_m;
  const double yaw_rate = gains.k_alpha_per_s * out.alpha_rad + gains.k_beta_per_s * out.beta_rad;
  out.curvature_per_m = yaw_rate / speed;
  // Reversed: the same path driven backwards, so v changes sign and ω = v κ keeps the turn
  // the turned-round robot makes, which is κ's sign flipped.
  out.speed_mps = reverse ? -speed : speed;
  if (reverse) out.curvature_per_m = -out.curvature_per_m;
  return out;
}

}  // namespace fleetnav::agent
