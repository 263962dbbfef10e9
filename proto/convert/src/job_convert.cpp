#include "fleetnav/proto/job_convert.hpp"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"

namespace fleetnav {

// JobState: the wire has PAUSED last (7); the domain keeps it after RUNNING.
v1::JobState ToProto(JobState state) {
  switch (state) {
    case JobState::kQueued:
      return v1::JOB_STATE_QUEUED;
    case JobState::kAssigned:
      return v1::JOB_STATE_ASSIGNED;
    case JobState::kRunning:
      return v1::JOB_STATE_RUNNING;
    case JobState::kPaused:
      return v1::JOB_STATE_PAUSED;
    case JobState::kSucceeded:
      return v1::JOB_STATE_SUCCEEDED;
    case JobState::kFailed:
      return v1::JOB_STATE_FAILED;
    case JobState::kCancelled:
      return v1::JOB_STATE_CANCELLED;
  }
  return v1::JOB_STATE_UNSPECIFIED;
}

absl::StatusOr<JobState> JobStateFromProto(int value) {
  switch (value) {
    case v1::JOB_STATE_QUEUED:
      return JobState::kQueued;
    case v1::JOB_STATE_ASSIGNED:
      return JobState::kAssigned;
    case v1::JOB_STATE_RUNNING:
      return JobState::kRunning;
    case v1::JOB_STATE_PAUSED:
      return JobState::kPaused;
    case v1::JOB_STATE_SUCCEEDED:
      return JobState::kSucceeded;
    case v1::JOB_STATE_FAILED:
      return JobState::kFailed;
    case v1::JOB_STATE_CANCELLED:
      return JobState::kCancelled;
    default:
      return absl::InvalidArgumentError(
          absl::StrCat("state: unspecified or unknown value ", value));
  }
}

v1::RequeuePolicy ToProto(RequeuePolicy policy) {
  return policy == RequeuePolicy::kRequeue ? v1::REQUEUE_POLICY_REQUEUE : v1::REQUEUE_POLICY_FAIL;
}

absl::StatusOr<RequeuePolicy> RequeuePolicyFromProto(int value) {
  switch (value) {
    case v1::REQUEUE_POLICY_UNSPECIFIED:
    case v1::REQUEUE_POLICY_FAIL:
      return RequeuePolicy::kFail;
    case v1::REQUEUE_POLICY_REQUEUE:
      return RequeuePolicy::kRequeue;
    default:
      return absl::InvalidArgumentError(absl::StrCat("on_robot_lost: unknown value ", value));
  }
}

v1::Job ToProto(const Job& job) {
  v1::Job out;
  out.set_job_id(job.job_id);
  out.set_state(ToProto(job.state));
  out.set_route_name(job.route_name);
  out.set_route_version(job.route_version);
  if (job.goal) {
    out.mutable_goal()->set_map_id(job.map_id);
    *out.mutable_goal()->mutable_goal() = ToProto(*job.goal);
  }
  out.set_robot_id(job.requested_robot_id);
  out.set_assigned_robot_id(job.assigned_robot_id);
  out.set_priority(job.priority);
  out.set_idempotency_key(job.idempotency_key);
  out.set_created_unix_ms(job.created_unix_ms);
  out.set_updated_unix_ms(job.updated_unix_ms);
  out.set_progress_fraction(job.progress_fraction);
  out.set_reason(job.reason);
  out.set_on_robot_lost(ToProto(job.on_robot_lost));
  return out;
}

absl::StatusOr<Job> FromProto(const v1::Job& job) {
  Job out;
  out.job_id = job.job_id();
  ASSIGN_OR_RETURN(out.state, JobStateFromProto(job.state()));
  out.route_name = job.route_name();
  out.route_version = job.route_version();
  if (job.has_goal()) {
    out.map_id = job.goal().map_id();
    ASSIGN_OR_RETURN(Pose2 goal, FromProto(job.goal().goal(), "job.goal.goal"));
    out.goal = goal;
  }
  out.requested_robot_id = job.robot_id();
  out.assigned_robot_id = job.assigned_robot_id();
  out.priority = job.priority();
  out.idempotency_key = job.idempotency_key();
  out.created_unix_ms = job.created_unix_ms();
  out.updated_unix_ms = job.updated_unix_ms();
  out.progress_fraction = job.progress_fraction();
  out.reason = job.reason();
  ASSIGN_OR_RETURN(out.on_robot_lost, RequeuePolicyFromProto(job.on_robot_lost()));
  return out;
}

// JobEventType values line up one to one after the UNSPECIFIED slot.
v1::JobEvent ToProto(const JobEvent& event) {
  v1::JobEvent out;
  out.set_job_id(event.job_id);
  out.set_type(static_cast<v1::JobEventType>(static_cast<int>(event.type) + 1));
  out.set_unix_ms(event.unix_ms);
  out.set_robot_id(event.robot_id);
  out.set_action_index(event.action_index);
  out.set_progress_fraction(event.progress_fraction);
  out.set_mode(ToProto(event.mode));
  out.set_reason(event.reason);
  out.set_state(ToProto(event.state));
  return out;
}

absl::StatusOr<JobEvent> JobEventFromAgentEvent(const v1::AgentEvent& event) {
  JobEvent out;
  switch (event.type()) {
    case v1::AgentEvent::TYPE_ACTION_STARTED:
      out.type = JobEventType::kActionStarted;
      break;
    case v1::AgentEvent::TYPE_ACTION_FINISHED:
      out.type = JobEventType::kActionFinished;
      break;
    case v1::AgentEvent::TYPE_JOB_SUCCEEDED:
      out.type = JobEventType::kSucceeded;
      break;
    case v1::AgentEvent::TYPE_JOB_FAILED:
      out.type = JobEventType::kFailed;
      break;
    case v1::AgentEvent::TYPE_JOB_CANCELLED:
      out.type = JobEventType::kCancelled;
      break;
    case v1::AgentEvent::TYPE_MODE_SWITCH:
      out.type = JobEventType::kModeSwitch;
      break;
    case v1::AgentEvent::TYPE_BUMPER:
      out.type = JobEventType::kBumper;
      break;
    case v1::AgentEvent::TYPE_LOCALIZATION_LOST:
      out.type = JobEventType::kLocalizationLost;
      break;
    default:
      return absl::InvalidArgumentError(
          absl::StrCat("event.type: not a job event (", static_cast<int>(event.type()), ")"));
  }
  if (event.job_id().empty()) return absl::InvalidArgumentError("event.job_id: empty");
  out.job_id = event.job_id();
  out.action_index = event.action_index();
  ASSIGN_OR_RETURN(out.mode, NavigationModeFromProto(event.mode()));
  out.reason = event.reason();
  return out;
}

v1::AgentEvent ToAgentEvent(const JobEvent& event, int64_t stamp_ns) {
  v1::AgentEvent out;
  switch (event.type) {
    case JobEventType::kActionStarted:
      out.set_type(v1::AgentEvent::TYPE_ACTION_STARTED);
      break;
    case JobEventType::kActionFinished:
      out.set_type(v1::AgentEvent::TYPE_ACTION_FINISHED);
      break;
    case JobEventType::kSucceeded:
      out.set_type(v1::AgentEvent::TYPE_JOB_SUCCEEDED);
      break;
    case JobEventType::kFailed:
      out.set_type(v1::AgentEvent::TYPE_JOB_FAILED);
      break;
    case JobEventType::kCancelled:
      out.set_type(v1::AgentEvent::TYPE_JOB_CANCELLED);
      break;
    case JobEventType::kBumper:
      out.set_type(v1::AgentEvent::TYPE_BUMPER);
      break;
    case JobEventType::kLocalizationLost:
      out.set_type(v1::AgentEvent::TYPE_LOCALIZATION_LOST);
      break;
    default:
      out.set_type(v1::AgentEvent::TYPE_MODE_SWITCH);
      break;
  }
  out.set_stamp_ns(stamp_ns);
  out.set_job_id(event.job_id);
  out.set_action_index(event.action_index);
  out.set_mode(ToProto(event.mode));
  out.set_reason(event.reason);
  return out;
}

absl::StatusOr<SubmitJobRequest> FromProto(const v1::SubmitJobRequest& request) {
  SubmitJobRequest submit;
  if (request.has_goal()) {
    ASSIGN_OR_RETURN(submit.goal, FromProto(request.goal().goal(), "goal.goal"));
    submit.goal_map_id = request.goal().map_id();
  } else {
    submit.route_name = request.route_name();
  }
  ASSIGN_OR_RETURN(submit.on_robot_lost, RequeuePolicyFromProto(request.on_robot_lost()));
  submit.robot_id = request.robot_id();
  submit.priority = request.priority();
  submit.idempotency_key = request.idempotency_key();
  return submit;
}

absl::StatusOr<JobFilter> FromProto(const v1::ListJobsRequest& request) {
  JobFilter filter;
  for (int state : request.states()) {
    absl::StatusOr<JobState> parsed = JobStateFromProto(state);
    if (!parsed.ok()) {
      return absl::InvalidArgumentError(
          absl::StrCat("states: unspecified or unknown value ", state));
    }
    filter.states.push_back(*parsed);
  }
  filter.robot_id = request.robot_id();
  filter.page_size = static_cast<int>(std::min<uint32_t>(request.page_size(), 1u << 30));
  filter.page_token = request.page_token();
  return filter;
}

}  // namespace fleetnav
