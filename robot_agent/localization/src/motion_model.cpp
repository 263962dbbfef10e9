#include "fleetnav/localization/motion_model.hpp"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"

namespace fleetnav::localization {
namespace {

float WrapFloat(float angle) {
  constexpr float kTwoPi = static_cast<float>(2.0 * kPi);
  constexpr float kPiF = static_cast<float>(kPi);
  if (angle > kPiF) angle -= kTwoPi;
  if (angle <= -kPiF) angle += kTwoPi;
  return angle;
}

}  // namespace

absl::Status MotionModelParams::Validate() const {
  const double all[] = {alpha1, alpha2, alpha3, alpha4, alpha5};
  for (size_t i = 0; i < 5; ++i) {
    if (!(std::isfinite(all[i]) && all[i] >= 0.0)) {
      return absl::InvalidArgumentError(
          absl::StrCat("alpha", i + 1, " must be finite and >= 0, got ", all[i]));
    }
  }
  return absl::OkStatus();
}

void SampleMotion(const MotionModelParams& p, const Pose2& odom_before, const Pose2& odom_after,
                  Rng& rng, float* x, float* y, float* yaw, size_t n) {
  const double dx = odom_after.x_m() - odom_before.x_m();
  const double dy = odom_after.y_m() - odom_before.y_m();
  const double dyaw = AngleDifference(odom_after.yaw_rad(), odom_before.yaw_rad());
  const double trans = std::hypot(dx, dy);
  if (trans == 0.0 && dyaw == 0.0) return;

  switch (p.kinematics) {
    case Kinematics::kDifferential: {
      double rot1 = trans < 0.01 ? 0.0 : AngleDifference(std::atan2(dy, dx), odom_before.yaw_rad());
      double signed_trans = trans;
      // Driving backwards: the heading of travel is opposite to the robot's.
      if (std::abs(rot1) > kPi / 2.0) {
        rot1 = NormalizeAngle(rot1 + kPi);
        signed_trans = -trans;
      }
      const double rot2 = AngleDifference(dyaw, rot1);
      // Noise is taken on the smaller of rot and rot+pi (as ROS amcl) so that reversing does not
      // look like a half turn.
      const double r1 = std::min(std::abs(rot1), std::abs(AngleDifference(rot1, kPi)));
      const double r2 = std::min(std::abs(rot2), std::abs(AngleDifference(rot2, kPi)));
      const double sd_rot1 = std::sqrt(p.alpha1 * r1 * r1 + p.alpha2 * trans * trans);
      const double sd_trans = std::sqrt(p.alpha3 * trans * trans + p.alpha4 * (r1 * r1 + r2 * r2));
      const double sd_rot2 = std::sqrt(p.alpha1 * r2 * r2 + p.alpha2 * trans * trans);
      for (size_t i = 0; i < n; ++i) {
        const double h_rot1 = rot1 + sd_rot1 * rng.Normal();
        const double h_trans = signed_trans + sd_trans * rng.Normal();
        const double h_rot2 = rot2 + sd_rot2 * rng.Normal();
        const double heading = yaw[i] + h_rot1;
        x[i] += static_cast<float>(h_trans * std::cos(heading));
        y[i] += static_cast<float>(h_trans * std::sin(heading));
        yaw[i] = WrapFloat(static_cast<float>(heading + h_rot2));
      }
      return;
    }
    case Kinematics::kOmnidirectional: {
      const double bearing = AngleDifference(std::atan2(dy, dx), odom_before.yaw_rad());
      const double sd_trans = std::sqrt(p.alpha3 * trans * trans + p.alpha1 * dyaw * dyaw);
      const double sd_rot = std::sqrt(p.alpha4 * dyaw * dyaw + p.alpha2 * trans * trans);
      const double sd_strafe = std::sqrt(p.alpha1 * dyaw * dyaw + p.alpha5 * trans * trans);
      for (size_t i = 0; i < n; ++i) {
        const double h_trans = trans + sd_trans * rng.Normal();
        const double h_rot = dyaw + sd_rot * rng.Normal();
        const double h_strafe = sd_strafe * rng.Normal();
        const double heading = yaw[i] + bearing;
        const double c = std::cos(heading);
        const double s = std::sin(heading);
        x[i] += static_cast<float>(h_trans * c - h_strafe * s);
        y[i] += static_cast<float>(h_trans * s + h_strafe * c);
        yaw[i] = WrapFloat(static_cast<float>(yaw[i] + h_rot));
      }
      return;
    }
    case Kinematics::kAckermann: {
      // Signed arc length along the odometry heading (the chord of a constant-curvature arc).
      const double mid = odom_before.yaw_rad() + 0.5 * dyaw;
      const double arc = dx * std::cos(mid) + dy * std::sin(mid);
      const double sd_arc = std::sqrt(p.alpha3 * arc * arc + p.alpha4 * dyaw * dyaw);
      const double sd_rot = std::sqrt(p.alpha1 * dyaw * dyaw + p.alpha2 * arc * arc);
      for (size_t i = 0; i < n; ++i) {
        const double h_arc = arc + sd_arc * rng.Normal();
        const double h_rot = dyaw + sd_rot * rng.Normal();
        const double heading = yaw[i] + 0.5 * h_rot;
        x[i] += static_cast<float>(h_arc * std::cos(heading));
        y[i] += static_cast<float>(h_arc * std::sin(heading));
        yaw[i] = WrapFloat(static_cast<float>(yaw[i] + h_rot));
      }
      return;
    }
  }
}

}  // namespace fleetnav::localization
