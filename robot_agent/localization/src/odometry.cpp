#include "fleetnav/localization/odometry.hpp"

#include <cmath>
#include <numbers>

#include "absl/strings/str_cat.h"

namespace fleetnav::localization {
namespace {

absl::Status Positive(double value, const char* field) {
  if (std::isfinite(value) && value > 0.0) return absl::OkStatus();
  return absl::InvalidArgumentError(absl::StrCat(field, " must be finite and > 0, got ", value));
}

}  // namespace

Pose2 IntegrateIncrement(const Pose2& pose, const BodyIncrement& increment) {
  const double mid_yaw = pose.yaw_rad() + 0.5 * increment.yaw_rad;
  const double c = std::cos(mid_yaw);
  const double s = std::sin(mid_yaw);
  return Pose2(pose.x_m() + c * increment.forward_m - s * increment.lateral_m,
               pose.y_m() + s * increment.forward_m + c * increment.lateral_m,
               pose.yaw_rad() + increment.yaw_rad);
}

absl::Status DiffDriveOdometryParams::Validate() const {
  if (absl::Status s = Positive(wheel_radius_m, "wheel_radius_m"); !s.ok()) return s;
  if (absl::Status s = Positive(track_m, "track_m"); !s.ok()) return s;
  if (encoder_ticks_per_rev <= 0) {
    return absl::InvalidArgumentError("encoder_ticks_per_rev must be > 0");
  }
  return absl::OkStatus();
}

BodyIncrement DiffDriveOdometry::Update(int64_t left_ticks, int64_t right_ticks) {
  BodyIncrement increment;
  if (last_ticks_.has_value()) {
    const double metres_per_tick =
        2.0 * std::numbers::pi * params_.wheel_radius_m / params_.encoder_ticks_per_rev;
    const double left_m = static_cast<double>(left_ticks - (*last_ticks_)[0]) * metres_per_tick;
    const double right_m = static_cast<double>(right_ticks - (*last_ticks_)[1]) * metres_per_tick;
    increment.forward_m = 0.5 * (left_m + right_m);
    increment.yaw_rad = (right_m - left_m) / params_.track_m;
    pose_ = IntegrateIncrement(pose_, increment);
  }
  last_ticks_ = std::array<int64_t, 2>{left_ticks, right_ticks};
  return increment;
}

absl::Status MecanumOdometryParams::Validate() const {
  if (absl::Status s =
          Positive(wheel_radius_m + roller_radius_m, "wheel_radius_m + roller_radius_m");
      !s.ok()) {
    return s;
  }
  if (!(roller_radius_m >= 0.0)) return absl::InvalidArgumentError("roller_radius_m must be >= 0");
  if (absl::Status s = Positive(half_wheelbase_m, "half_wheelbase_m"); !s.ok()) return s;
  return Positive(half_track_m, "half_track_m");
}

Eigen::Vector3d MecanumOdometry::ForwardKinematics(const std::array<double, 4>& w) const {
  const double r = params_.wheel_radius_m + params_.roller_radius_m;
  const double t = params_.half_wheelbase_m + params_.half_track_m;
  return {r / 4.0 * (w[0] + w[1] + w[2] + w[3]),          // eq. 4.15
          r / 4.0 * (-w[0] + w[1] + w[2] - w[3]),         // eq. 4.16
          r / (4.0 * t) * (-w[0] + w[1] - w[2] + w[3])};  // eq. 4.17
}

std::array<double, 4> MecanumOdometry::InverseKinematics(const Eigen::Vector3d& v) const {
  const double r = params_.wheel_radius_m + params_.roller_radius_m;
  const double t = params_.half_wheelbase_m + params_.half_track_m;
  return {(v.x() - v.y() - v.z() * t) / r, (v.x() + v.y() + v.z() * t) / r,
          (v.x() + v.y() - v.z() * t) / r, (v.x() - v.y() + v.z() * t) / r};
}

BodyIncrement MecanumOdometry::Update(const std::array<double, 4>& wheel_increments_rad) {
  const Eigen::Vector3d d = ForwardKinematics(wheel_increments_rad);
  const BodyIncrement increment{d.x(), d.y(), d.z()};
  pose_ = IntegrateIncrement(pose_, increment);
  return increment;
}

absl::Status AckermannOdometryParams::Validate() const {
  return Positive(wheelbase_m, "wheelbase_m");
}

BodyIncrement AckermannOdometry::Update(double rear_arc_m, double steering_rad) {
  const BodyIncrement increment{rear_arc_m, 0.0,
                                rear_arc_m * std::tan(steering_rad) / params_.wheelbase_m};
  pose_ = IntegrateIncrement(pose_, increment);
  return increment;
}

}  // namespace fleetnav::localization
