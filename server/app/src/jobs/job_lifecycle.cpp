#include "fleetnav/server/jobs/job_lifecycle.hpp"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/server/site/map_catalog.hpp"

namespace fleetnav::server {

absl::StatusOr<storage::CreatedJob> JobLifecycle::Submit(const SubmitJobRequest& request) {
  Job job;
  std::vector<NeededCapability> needs;
  std::shared_ptr<const storage::StoredMap> goal_map;  // a goal's
  const bool has_route = !request.route_name.empty();
  if (has_route == request.goal.has_value()) {
    return absl::InvalidArgumentError("target: give either `route_name` or `goal`");
  }
  if (has_route) {
    ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredRoute> route,
                     site_->GetRoute(request.route_name, 0));
    RETURN_IF_ERROR(site_->CheckRouteOutsideNoGo(route->route));
    job.route_name = route->route.name;
    job.route_version = route->version;
    job.map_id = route->route.map_id;
    needs = NeedsOfRoute(route->route);
  } else {
    if (!request.goal->IsFinite()) return absl::InvalidArgumentError("goal.goal: must be finite");
    RETURN_IF_ERROR(MapCatalog::ValidateMapId(request.goal_map_id));
    ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredMap> map,
                     site_data_->Map(request.goal_map_id, 0));
    const std::optional<CellIndex> cell = map->grid.WorldToCell(request.goal->translation());
    if (!cell) return absl::InvalidArgumentError("goal.goal: outside the map");
    if (map->grid.State(*cell) != CellState::kFree) {
      return absl::InvalidArgumentError("goal.goal: not on a free cell of the map");
    }
    RETURN_IF_ERROR(
        site_->CheckOutsideNoGo(request.goal_map_id, request.goal->translation(), "goal.goal"));
    goal_map = std::move(map);
    job.map_id = request.goal_map_id;
    job.goal = request.goal;
    needs = NeedsOfGoal();
  }
  if (!request.robot_id.empty()) {
    ASSIGN_OR_RETURN(const RobotRecord robot, registry_->Get(request.robot_id));
    RETURN_IF_ERROR(CheckRobotCanRun(robot, needs));
  }
  if (goal_map) RETURN_IF_ERROR(CheckGoalReachable(request, *goal_map));
  if (request.idempotency_key.size() > 128) {
    return absl::InvalidArgumentError("idempotency_key: at most 128 characters");
  }
  job.requested_robot_id = request.robot_id;
  job.priority = request.priority;
  job.idempotency_key = request.idempotency_key;
  job.on_robot_lost = request.on_robot_lost;
  absl::StatusOr<storage::CreatedJob> created = ledger_->Create(job);
  if (created.ok() && !created->deduplicated) work_->Notify();
  return created;
}

absl::Status JobLifecycle::CheckGoalReachable(const SubmitJobRequest& request,
                                              const storage::StoredMap& map) {
  std::vector<RobotRecord> robots;
  if (!request.robot_id.empty()) {
    absl::StatusOr<RobotRecord> named = registry_->Get(request.robot_id);
    if (!named.ok()) return named.status();
    robots.push_back(*std::move(named));
  } else {
    // A goal on a site whose robots do not navigate freely (loadgen's thousands of agents) costs
    // no copy of the fleet.
    if (!registry_->KnownCapabilities().contains("free_navigation")) return absl::OkStatus();
    robots = registry_->Snapshot();
    std::erase_if(robots, [](const RobotRecord& robot) {
      const std::vector<std::string>& have = robot.identity.capabilities;
      return std::find(have.begin(), have.end(), "free_navigation") == have.end();
    });
  }
  // A robot that is away may be anywhere when it comes back: only its footprint is checked.
  std::string refusal;
  for (const RobotRecord& robot : robots) {
    std::optional<Pose2> from;
    if (robot.connection != ConnectionState::kOffline && robot.last_telemetry) {
      from = robot.last_telemetry->pose_in_map;
    }
    const absl::Status reachable = reachability_.Check(
        request.goal_map_id, map.info.version, robot.identity.model, request.goal->translation(),
        from,
        absl::StrCat("robot ", robot.identity.robot_id, " (", robot.identity.model.kind_name, ")"));
    if (reachable.ok()) return absl::OkStatus();
    if (!absl::IsFailedPrecondition(reachable)) return reachable;
    if (refusal.empty()) refusal = std::string(reachable.message());
  }
  if (refusal.empty()) return absl::OkStatus();  // no robot known yet
  return absl::FailedPreconditionError(
      absl::StrCat("goal.goal: ",
                   robots.size() > 1 ? absl::StrCat("none of the ", robots.size(),
                                                    " robots that navigate freely can go there; ")
                                     : "",
                   refusal));
}

absl::Status JobLifecycle::CheckRobotCanRun(const RobotRecord& robot,
                                            const std::vector<NeededCapability>& needs) {
  // A connected robot says what it can run; one that is away may come back with new software.
  if (robot.connection == ConnectionState::kOffline) return absl::OkStatus();
  const std::vector<std::string>& have = robot.identity.capabilities;
  const std::optional<NeededCapability> unmet =
      FirstUnmet(needs, [&](const std::string& capability) {
        return std::find(have.begin(), have.end(), capability) != have.end();
      });
  if (!unmet) return absl::OkStatus();
  return absl::FailedPreconditionError(absl::StrCat(
      "robot_id: robot ", robot.identity.robot_id, " (", robot.identity.model.kind_name,
      ") cannot run ", unmet->Describe(), "; it runs ", absl::StrJoin(have, ", ")));
}

absl::StatusOr<Job> JobLifecycle::Cancel(const std::string& job_id, const std::string& reason) {
  ASSIGN_OR_RETURN(Job job, ledger_->Get(job_id));
  if (IsTerminal(job.state)) {
    return absl::FailedPreconditionError(
        absl::StrCat("job '", job_id, "' has already ", std::string(JobStateName(job.state))));
  }
  const std::string robot = job.assigned_robot_id;
  const std::string why = reason.empty() ? "cancelled by operator" : reason;
  RETURN_IF_ERROR(
      ledger_->Transition(job, JobState::kCancelled, JobEventType::kCancelled, why, robot));
  TakeFromRobot(job_id, robot, why);
  return job;
}

void JobLifecycle::TakeFromRobot(const std::string& job_id, const std::string& robot_id,
                                 const std::string& why) {
  recovery_->Forget(job_id);
  traffic_->End(job_id);
  if (robot_id.empty()) return;
  mailbox_->SendCommand(robot_id, JobCommand{JobCommandType::kCancel, job_id, why});
  registry_->SetCurrentJob(robot_id, "");
  work_->Notify();  // the robot is free for the next job
}

absl::StatusOr<Job> JobLifecycle::Withdraw(const std::string& job_id, const std::string& reason) {
  ASSIGN_OR_RETURN(Job job, ledger_->Get(job_id));
  if (job.state != JobState::kAssigned) {
    return absl::FailedPreconditionError(absl::StrCat("job '", job_id, "' is ",
                                                      std::string(JobStateName(job.state)),
                                                      "; only an assigned job is withdrawn"));
  }
  const std::string robot = job.assigned_robot_id;
  job.assigned_robot_id.clear();
  RETURN_IF_ERROR(
      ledger_->Transition(job, JobState::kQueued, JobEventType::kQueued, reason, robot));
  TakeFromRobot(job_id, robot, reason);
  return job;
}

absl::StatusOr<Job> JobLifecycle::Pause(const std::string& job_id, const std::string& reason) {
  ASSIGN_OR_RETURN(Job job, ledger_->Get(job_id));
  if (job.state != JobState::kAssigned && job.state != JobState::kRunning) {
    return absl::FailedPreconditionError(absl::StrCat("job '", job_id, "' is ",
                                                      std::string(JobStateName(job.state)),
                                                      "; only an assigned or running job pauses"));
  }
  const std::string why = reason.empty() ? "paused by operator" : reason;
  RETURN_IF_ERROR(ledger_->Transition(job, JobState::kPaused, JobEventType::kPaused, why,
                                      job.assigned_robot_id));
  mailbox_->SendCommand(job.assigned_robot_id, JobCommand{JobCommandType::kPause, job_id, why});
  return job;
}

absl::StatusOr<Job> JobLifecycle::Resume(const std::string& job_id) {
  ASSIGN_OR_RETURN(Job job, ledger_->Get(job_id));
  if (job.state != JobState::kPaused) {
    return absl::FailedPreconditionError(absl::StrCat(
        "job '", job_id, "' is ", std::string(JobStateName(job.state)), ", not paused"));
  }
  absl::StatusOr<RobotRecord> robot = registry_->Get(job.assigned_robot_id);
  if (!robot.ok() || robot->connection == ConnectionState::kOffline || recovery_->IsAway(job_id)) {
    return absl::FailedPreconditionError(
        absl::StrCat("robot '", job.assigned_robot_id,
                     "' is offline; the job resumes when it reconnects with it"));
  }
  RETURN_IF_ERROR(ledger_->Transition(job, JobState::kRunning, JobEventType::kResumed,
                                      "resumed by operator", job.assigned_robot_id));
  mailbox_->SendCommand(job.assigned_robot_id,
                        JobCommand{JobCommandType::kResume, job_id, "resumed by operator"});
  return job;
}

void JobLifecycle::End(Job& job, JobState state, const JobEvent& event,
                       const std::string& robot_id) {
  if (state == JobState::kSucceeded) job.progress_fraction = 1.0;
  const JobEventType type =
      state == JobState::kSucceeded ? JobEventType::kSucceeded : JobEventType::kFailed;
  (void)ledger_->Transition(job, state, type, event.reason, robot_id);
  registry_->SetCurrentJob(robot_id, "");
  work_->Notify();
  traffic_->End(job.job_id);
  traffic_->Update();
}

void JobLifecycle::OnRobotEvent(const std::string& robot_id, const JobEvent& event) {
  absl::StatusOr<Job> found = ledger_->Get(event.job_id);
  if (!found.ok() || found->assigned_robot_id != robot_id || IsTerminal(found->state)) return;
  Job job = *found;
  switch (event.type) {
    case JobEventType::kSucceeded:
      End(job, JobState::kSucceeded, event, robot_id);
      return;
    case JobEventType::kFailed:
      End(job, JobState::kFailed, event, robot_id);
      return;
    case JobEventType::kActionStarted:
    case JobEventType::kActionFinished:
    case JobEventType::kModeSwitch:
    case JobEventType::kBumper:
    case JobEventType::kLocalizationLost: {
      const bool starts = job.state == JobState::kAssigned;
      if (starts) {
        job.state = JobState::kRunning;
        (void)ledger_->Record(
            job, ledger_->MakeEvent(job, JobEventType::kStarted, event.reason, robot_id));
      }
      JobEvent stored = ledger_->MakeEvent(job, event.type, event.reason, robot_id);
      stored.action_index = event.action_index;
      stored.mode = event.mode;
      (void)ledger_->Record(job, stored);
      if (event.type == JobEventType::kActionFinished) {
        traffic_->OnActionFinished(robot_id, job.job_id, event.action_index);
      }
      return;
    }
    default:
      return;
  }
}

void JobLifecycle::OnTelemetry(const std::string& robot_id, const Telemetry& telemetry) {
  if (telemetry.job_id.empty()) return;
  // JobService checked this before taking its lock; checked again here, under it, so that two
  // reports of the same step racing to the lock store one event.
  if (!ledger_->IsNewProgressStep(telemetry.job_id, telemetry.job_progress_fraction)) return;
  absl::StatusOr<Job> job = ledger_->Get(telemetry.job_id);
  if (!job.ok() || job->assigned_robot_id != robot_id || job->state != JobState::kRunning) return;
  ledger_->NoteProgressStored(telemetry.job_id, telemetry.job_progress_fraction);
  job->progress_fraction = std::clamp(telemetry.job_progress_fraction, 0.0, 1.0);
  job->updated_unix_ms = ledger_->NowUnixMs();
  JobEvent event = ledger_->MakeEvent(*job, JobEventType::kProgress, "", robot_id);
  event.action_index = telemetry.action_index;
  event.mode = telemetry.mode;
  (void)ledger_->Record(*job, event);
}

}  // namespace fleetnav::server
