#pragma once

#include "absl/status/statusor.h"
#include "fleetnav/core/job_assignment.hpp"
#include "fleetnav/v1/agent_service.pb.h"

namespace fleetnav {

/// Wire <-> domain for what the server sends a robot about its job: the assignment, and the
/// pause / resume / cancel commands and traffic clearances as JobCommand.
v1::Assignment ToProto(const JobAssignment& assignment);
/// InvalidArgument naming the job or route field that does not convert.
absl::StatusOr<JobAssignment> FromProto(const v1::Assignment& assignment);
/// kPause, kResume or kCancel (a clearance travels as v1::TrafficClearance).
v1::Command ToProto(const JobCommand& command);
/// InvalidArgument for an unspecified or unknown command type.
absl::StatusOr<JobCommand> FromProto(const v1::Command& command);
/// A clearance as the server sends it (a wait before the blocker's first action goes as 0).
v1::TrafficClearance ToProto(const ClearanceNotice& clearance);
/// A traffic clearance as a kClearance command (its wait reason as the reason).
/// InvalidArgument for a hold whose gate is not finite (the clearance is not acted on).
absl::StatusOr<JobCommand> FromProto(const v1::TrafficClearance& clearance);

}  // namespace fleetnav
