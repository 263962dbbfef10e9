#pragma once

#include "absl/status/statusor.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/v1/types.pb.h"

namespace fleetnav {

/// Wire <-> domain for robot models; FromProto refuses UNSPECIFIED or unknown enum values and
/// runs RobotModel::Validate().
v1::RobotModel ToProto(const RobotModel& model);
absl::StatusOr<RobotModel> FromProto(const v1::RobotModel& model);

}  // namespace fleetnav
