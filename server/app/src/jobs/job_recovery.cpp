#include "fleetnav/server/jobs/job_recovery.hpp"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::server {

absl::Status JobRecovery::RestoreAfterRestart() {
  ASSIGN_OR_RETURN(std::vector<storage::StoredRobot> robots, robots_->ListRobots());
  for (const storage::StoredRobot& stored : robots) {
    RobotIdentity identity;
    identity.robot_id = stored.robot_id;
    absl::StatusOr<RobotModel> model = RobotModelByKind(stored.kind_name);
    if (model.ok()) identity.model = *model;
    identity.model.kind_name = stored.kind_name;
    identity.capabilities = stored.capabilities;
    identity.software_version = stored.software_version;
    registry_->RestoreOffline(identity);
  }
  storage::JobFilter in_flight;
  in_flight.states = {JobState::kAssigned, JobState::kRunning, JobState::kPaused};
  in_flight.page_size = params_.max_page_size;
  while (true) {
    ASSIGN_OR_RETURN(storage::JobPage page, ledger_->List(in_flight));
    for (Job& job : page.jobs) {
      if (job.state != JobState::kPaused) {
        RETURN_IF_ERROR(ledger_->Transition(job, JobState::kPaused, JobEventType::kPaused,
                                            "server restarted; waiting for the robot to reconnect",
                                            job.assigned_robot_id));
      }
      away_since_ns_[job.job_id] = clock_->NowNs();
      registry_->SetCurrentJob(job.assigned_robot_id, job.job_id);
      // Coordinated from where the robot reports when it is back; until then it holds the
      // others on its map (it may stand in their way).
      if (absl::StatusOr<JobAssignment> held = ResolveAssignment(job, *site_, *site_data_);
          held.ok()) {
        traffic_->Resume(job.assigned_robot_id, *held);
      }
    }
    if (page.next_page_token.empty()) break;
    in_flight.page_token = page.next_page_token;
  }
  return absl::OkStatus();
}

void JobRecovery::OnRobotConnected(const RobotIdentity& identity,
                                   const std::string& resume_job_id) {
  (void)robots_->UpsertRobot(storage::StoredRobot{identity.robot_id, identity.model.kind_name,
                                                  identity.capabilities, identity.software_version,
                                                  ledger_->NowUnixMs()});
  storage::JobFilter held;
  held.robot_id = identity.robot_id;
  held.states = {JobState::kPaused, JobState::kAssigned, JobState::kRunning};
  held.page_size = 10;
  absl::StatusOr<storage::JobPage> page = ledger_->List(held);
  if (!page.ok()) return;
  for (Job& job : page->jobs) {
    if (job.assigned_robot_id != identity.robot_id) continue;
    // A job an operator paused stays paused whatever the link did.
    const bool held_by_operator = job.state == JobState::kPaused && !IsAway(job.job_id);
    away_since_ns_.erase(job.job_id);
    if (job.job_id == resume_job_id) {
      if (held_by_operator) {
        mailbox_->SendCommand(identity.robot_id,
                              JobCommand{JobCommandType::kPause, job.job_id, job.reason});
      } else {
        (void)ledger_->Transition(job, JobState::kRunning, JobEventType::kResumed,
                                  "robot reconnected", identity.robot_id);
      }
      registry_->SetCurrentJob(identity.robot_id, job.job_id);
      if (absl::StatusOr<JobAssignment> resumed = ResolveAssignment(job, *site_, *site_data_);
          resumed.ok()) {
        traffic_->Resume(identity.robot_id, *resumed);
      }
    } else if (std::optional<RoutePosition> left_off = WhereRobotLeftOff(identity.robot_id, job);
               left_off && SendAgain(identity.robot_id, job, *left_off, held_by_operator)) {
      // Its agent restarted: the job goes on from where the robot stands.
    } else if (job.on_robot_lost == RequeuePolicy::kRequeue) {
      job.assigned_robot_id.clear();
      traffic_->End(job.job_id);
      (void)ledger_->Transition(job, JobState::kQueued, JobEventType::kQueued,
                                "robot reconnected without the job; re-queued", identity.robot_id);
      registry_->SetCurrentJob(identity.robot_id, "");
    } else {
      traffic_->End(job.job_id);
      (void)ledger_->Transition(job, JobState::kFailed, JobEventType::kFailed,
                                "robot reconnected without the job", identity.robot_id);
      registry_->SetCurrentJob(identity.robot_id, "");
    }
  }
  // The robot may still drive a job that ended or went elsewhere while it was away: it is told
  // before it can be handed another (its outbox delivers in order).
  if (!resume_job_id.empty()) CancelJobNoLongerHeld(identity.robot_id, resume_job_id);
}

std::optional<RoutePosition> JobRecovery::WhereRobotLeftOff(const std::string& robot_id,
                                                            const Job& job) {
  absl::StatusOr<RobotRecord> record = registry_->Get(robot_id);
  if (!record.ok() || !record->last_telemetry || record->last_telemetry->job_id != job.job_id) {
    return std::nullopt;
  }
  const Telemetry& last = *record->last_telemetry;
  if (last.action_index < 0) return RoutePosition{};  // it had not begun
  return RoutePosition{last.action_index, last.action_progress_fraction};
}

bool JobRecovery::SendAgain(const std::string& robot_id, Job& job, const RoutePosition& from,
                            bool held_by_operator) {
  absl::StatusOr<JobAssignment> assignment = ResolveAssignment(job, *site_, *site_data_);
  if (!assignment.ok() || !CheckRoutePosition(*assignment->route, from).ok()) return false;
  assignment->resume = from;
  if (!mailbox_->SendAssignment(robot_id, *assignment)) return false;
  const std::string why = absl::StrFormat(
      "robot came back without the job (its agent restarted): sent again from "
      "action %d, %.0f %% of it done",
      from.action_index, 100.0 * from.action_fraction);
  if (held_by_operator) {
    mailbox_->SendCommand(robot_id, JobCommand{JobCommandType::kPause, job.job_id, job.reason});
    (void)ledger_->Record(job, ledger_->MakeEvent(job, JobEventType::kPaused, why, robot_id));
  } else {
    (void)ledger_->Transition(job, JobState::kRunning, JobEventType::kResumed, why, robot_id);
  }
  registry_->SetCurrentJob(robot_id, job.job_id);
  traffic_->Resume(robot_id, *assignment);
  return true;
}

void JobRecovery::CancelJobNoLongerHeld(const std::string& robot_id, const std::string& job_id) {
  absl::StatusOr<Job> job = ledger_->Get(job_id);
  if (job.ok() && job->assigned_robot_id == robot_id && !IsTerminal(job->state)) return;
  std::string why;
  if (!job.ok()) {
    why = "the server does not know this job";
  } else if (IsTerminal(job->state)) {
    why = absl::StrCat("the job ", std::string(JobStateName(job->state)),
                       " while the robot was away", job->reason.empty() ? "" : ": ", job->reason);
  } else if (!job->assigned_robot_id.empty()) {
    why = absl::StrCat("the job was given to robot ", job->assigned_robot_id,
                       " while this robot was away");
  } else {
    why = "the job was re-queued while this robot was away";
  }
  mailbox_->SendCommand(robot_id, JobCommand{JobCommandType::kCancel, job_id, why});
}

void JobRecovery::OnRobotDisconnected(const std::string& robot_id) {
  absl::StatusOr<RobotRecord> record = registry_->Get(robot_id);
  if (!record.ok() || record->current_job_id.empty()) return;
  absl::StatusOr<Job> job = ledger_->Get(record->current_job_id);
  if (!job.ok() || IsTerminal(job->state) || job->state == JobState::kPaused) return;
  (void)ledger_->Transition(*job, JobState::kPaused, JobEventType::kPaused, "robot disconnected",
                            robot_id);
  away_since_ns_[job->job_id] = clock_->NowNs();
}

void JobRecovery::ExpireLostRobots() {
  const int64_t now_ns = clock_->NowNs();
  for (auto it = away_since_ns_.begin(); it != away_since_ns_.end();) {
    if (static_cast<double>(now_ns - it->second) * 1e-9 < params_.lost_robot_timeout_s) {
      ++it;
      continue;
    }
    absl::StatusOr<Job> job = ledger_->Get(it->first);
    it = away_since_ns_.erase(it);
    if (!job.ok() || job->state != JobState::kPaused) continue;
    const std::string robot = job->assigned_robot_id;
    registry_->SetCurrentJob(robot, "");
    traffic_->End(job->job_id);
    // The reason names the robot and how long it was away.
    const std::string lost =
        absl::StrCat("robot ", robot, " lost for ", params_.lost_robot_timeout_s, " s");
    if (job->on_robot_lost == RequeuePolicy::kRequeue) {
      job->assigned_robot_id.clear();
      (void)ledger_->Transition(*job, JobState::kQueued, JobEventType::kQueued,
                                lost + "; re-queued by policy", robot);
    } else {
      (void)ledger_->Transition(*job, JobState::kFailed, JobEventType::kFailed, lost, robot);
    }
  }
}

}  // namespace fleetnav::server
