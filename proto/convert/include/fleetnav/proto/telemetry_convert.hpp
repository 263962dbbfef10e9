#pragma once

#include "absl/status/statusor.h"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/v1/agent_service.pb.h"
#include "fleetnav/v1/types.pb.h"

namespace fleetnav {

/// Wire <-> domain for what robots report. FromProto refuses non-finite poses and unknown
/// enum values, naming the field.
v1::Telemetry ToProto(const Telemetry& telemetry);
absl::StatusOr<Telemetry> FromProto(const v1::Telemetry& telemetry);

v1::NavigationMode ToProto(NavigationMode mode);
absl::StatusOr<NavigationMode> NavigationModeFromProto(int value);

v1::ConnectionState ToProto(ConnectionState state);
/// The wire form of the fleet server's record of a robot.
v1::RobotState ToProto(const RobotRecord& record);

/// The identity in an agent's hello; the robot id must be non-empty ([A-Za-z0-9_.-]{1,64}).
absl::StatusOr<RobotIdentity> FromProto(const v1::AgentHello& hello);
v1::AgentHello ToProto(const RobotIdentity& identity);

}  // namespace fleetnav
