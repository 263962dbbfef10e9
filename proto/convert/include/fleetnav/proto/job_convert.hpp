#pragma once

#include "absl/status/statusor.h"
#include "fleetnav/core/job.hpp"
#include "fleetnav/v1/agent_service.pb.h"
#include "fleetnav/v1/fleet_service.pb.h"

namespace fleetnav {

/// Wire <-> domain for jobs, their events and the job events robots report.
v1::Job ToProto(const Job& job);
absl::StatusOr<Job> FromProto(const v1::Job& job);
v1::JobState ToProto(JobState state);
absl::StatusOr<JobState> JobStateFromProto(int value);
v1::JobEvent ToProto(const JobEvent& event);
v1::RequeuePolicy ToProto(RequeuePolicy policy);
absl::StatusOr<RequeuePolicy> RequeuePolicyFromProto(int value);
/// InvalidArgument naming `goal.goal` (a pose that is not finite) or `on_robot_lost`.
absl::StatusOr<SubmitJobRequest> FromProto(const v1::SubmitJobRequest& request);
/// InvalidArgument naming `states` for an unspecified or unknown state; page sizes beyond 2^30
/// are taken as 2^30.
absl::StatusOr<JobFilter> FromProto(const v1::ListJobsRequest& request);

/// A robot's AgentEvent as a job event; InvalidArgument for an unknown type or no job id.
absl::StatusOr<JobEvent> JobEventFromAgentEvent(const v1::AgentEvent& event);
v1::AgentEvent ToAgentEvent(const JobEvent& event, int64_t stamp_ns);

}  // namespace fleetnav
