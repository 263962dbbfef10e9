#pragma once

#include <string>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/v1/types.pb.h"

namespace fleetnav {

/// Wire <-> domain for SE(2) poses. FromProto refuses non-finite values with InvalidArgument
/// naming `field`.
v1::Pose2 ToProto(const Pose2& pose);
absl::StatusOr<Pose2> FromProto(const v1::Pose2& pose, const std::string& field = "pose");

v1::Point2 ToProto(const Eigen::Vector2d& point);
absl::StatusOr<Eigen::Vector2d> FromProto(const v1::Point2& point,
                                          const std::string& field = "point");

}  // namespace fleetnav
