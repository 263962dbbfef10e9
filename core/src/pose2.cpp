#include "fleetnav/core/pose2.hpp"

#include <cmath>

#include "absl/strings/str_format.h"
#include "fleetnav/core/angles.hpp"

namespace fleetnav {

Pose2::Pose2(double x_m, double y_m, double yaw_rad)
    : x_m_(x_m), y_m_(y_m), yaw_rad_(NormalizeAngle(yaw_rad)) {}

Pose2 Pose2::operator*(const Pose2& other) const {
  const double c = std::cos(yaw_rad_);
  const double s = std::sin(yaw_rad_);
  return Pose2(x_m_ + c * other.x_m_ - s * other.y_m_, y_m_ + s * other.x_m_ + c * other.y_m_,
               yaw_rad_ + other.yaw_rad_);
}

Pose2 Pose2::Inverse() const {
  const double c = std::cos(yaw_rad_);
  const double s = std::sin(yaw_rad_);
  return Pose2(-c * x_m_ - s * y_m_, s * x_m_ - c * y_m_, -yaw_rad_);
}

Eigen::Vector2d Pose2::TransformPoint(const Eigen::Vector2d& point) const {
  const double c = std::cos(yaw_rad_);
  const double s = std::sin(yaw_rad_);
  return {x_m_ + c * point.x() - s * point.y(), y_m_ + s * point.x() + c * point.y()};
}

Eigen::Isometry2d Pose2::ToIsometry() const {
  Eigen::Isometry2d iso = Eigen::Isometry2d::Identity();
  iso.linear() = Eigen::Rotation2Dd(yaw_rad_).toRotationMatrix();
  iso.translation() = translation();
  return iso;
}

Pose2 Pose2::FromIsometry(const Eigen::Isometry2d& iso) {
  const Eigen::Matrix2d rotation = iso.linear();
  return Pose2(iso.translation().x(), iso.translation().y(),
               std::atan2(rotation(1, 0), rotation(0, 0)));
}

bool Pose2::IsNear(const Pose2& other, double tolerance_m, double tolerance_rad) const {
  return (translation() - other.translation()).norm() <= tolerance_m &&
         std::abs(AngleDifference(yaw_rad_, other.yaw_rad_)) <= tolerance_rad;
}

bool Pose2::IsFinite() const {
  return std::isfinite(x_m_) && std::isfinite(y_m_) && std::isfinite(yaw_rad_);
}

std::string Pose2::DebugString() const {
  return absl::StrFormat("Pose2(x=%.4f m, y=%.4f m, yaw=%.4f rad)", x_m_, y_m_, yaw_rad_);
}

Pose2 Between(const Pose2& a, const Pose2& b) { return a.Inverse() * b; }

}  // namespace fleetnav
