#include "fleetnav/proto/geometry_convert.hpp"

#include <cmath>

#include "absl/strings/str_cat.h"

namespace fleetnav {

v1::Pose2 ToProto(const Pose2& pose) {
  v1::Pose2 out;
  out.set_x_m(pose.x_m());
  out.set_y_m(pose.y_m());
  out.set_yaw_rad(pose.yaw_rad());
  return out;
}

absl::StatusOr<Pose2> FromProto(const v1::Pose2& pose, const std::string& field) {
  if (!std::isfinite(pose.x_m()) || !std::isfinite(pose.y_m()) || !std::isfinite(pose.yaw_rad())) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": pose components must be finite, got (",
                                                   pose.x_m(), ", ", pose.y_m(), ", ",
                                                   pose.yaw_rad(), ")"));
  }
  return Pose2(pose.x_m(), pose.y_m(), pose.yaw_rad());
}

v1::Point2 ToProto(const Eigen::Vector2d& point) {
  v1::Point2 out;
  out.set_x_m(point.x());
  out.set_y_m(point.y());
  return out;
}

absl::StatusOr<Eigen::Vector2d> FromProto(const v1::Point2& point, const std::string& field) {
  if (!std::isfinite(point.x_m()) || !std::isfinite(point.y_m())) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": point components must be finite"));
  }
  return Eigen::Vector2d(point.x_m(), point.y_m());
}

}  // namespace fleetnav
