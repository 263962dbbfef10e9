#pragma once

#include "absl/status/statusor.h"
#include "fleetnav/core/sensor_frame.hpp"
#include "fleetnav/v1/sim_service.pb.h"

namespace fleetnav {

/// Wire <-> domain for the lockstep sensor frames and actuator commands of SimService.
v1::SensorFrame ToProto(const SensorFrame& frame);
SensorFrame FromProto(const v1::SensorFrame& frame);

v1::ActuatorCommand ToProto(const ActuatorCommand& command);
/// InvalidArgument for a command with no drive set or non-finite values.
absl::StatusOr<ActuatorCommand> FromProto(const v1::ActuatorCommand& command);

}  // namespace fleetnav
