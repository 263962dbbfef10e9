#include "fleetnav/server/job_service.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/time/clock.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/server/map_catalog.hpp"

namespace fleetnav::server {
namespace {

/// Added to the straight-line distance of a robot with no path to a job's start: it is
/// considered only when no robot has one.
constexpr double kNoPathRankM = 1e6;

int64_t NowUnixMs() { return absl::ToUnixMillis(absl::Now()); }

JobEvent MakeEvent(const Job& job, JobEventType type, const std::string& reason,
                   const std::string& robot_id) {
  JobEvent event;
  event.job_id = job.job_id;
  event.type = type;
  event.unix_ms = NowUnixMs();
  event.robot_id = robot_id;
  event.progress_fraction = job.progress_fraction;
  event.reason = reason;
  event.state = job.state;
  return event;
}

}  // namespace

absl::Status JobServiceParams::Validate() const {
  if (!std::isfinite(lost_robot_timeout_s) || lost_robot_timeout_s <= 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("lost_robot_timeout_s: must be finite and > 0, got ", lost_robot_timeout_s));
  }
  if (max_page_size < 1) return absl::InvalidArgumentError("max_page_size: must be >= 1");
  if (!(charge_below_fraction >= 0.0 && charge_below_fraction < charged_fraction &&
        charged_fraction <= 1.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("charging: need 0 <= below_fraction < charged_fraction <= 1, got ",
                     charge_below_fraction, " and ", charged_fraction));
  }
  if (!std::isfinite(evict_offline_robots_after_s) || evict_offline_robots_after_s < 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("evict_offline_robots_after_s: must be finite and >= 0, got ",
                     evict_offline_robots_after_s));
  }
  return absl::OkStatus();
}

JobService::JobService(storage::JobRepository* jobs, storage::RobotRepository* robots,
                       SiteCache* site_data, SiteCatalog* site, FleetRegistry* registry,
                       RobotMailbox* mailbox, const Clock* clock, JobServiceParams params,
                       TrafficCoordinator* traffic)
    : jobs_(jobs),
      robots_(robots),
      site_data_(site_data),
      site_(site),
      registry_(registry),
      mailbox_(mailbox),
      clock_(clock),
      params_(params),
      traffic_(traffic),
      travel_(site_data) {}

void JobService::EndTraffic(const std::string& job_id) {
  if (traffic_ != nullptr) traffic_->End(job_id);
}

void JobService::UpdateTraffic() {
  if (traffic_ == nullptr) return;
  for (const TrafficWaitChange& change : traffic_->Update()) {
    if (change.reason.empty()) continue;
    absl::StatusOr<Job> job = jobs_->GetJob(change.job_id);
    if (!job.ok() || IsTerminal(job->state)) continue;
    (void)jobs_->UpdateJob(
        *job, MakeEvent(*job, JobEventType::kWaitingForTraffic, change.reason, change.robot_id));
  }
}

absl::Status JobService::Transition(Job& job, JobState state, JobEventType type,
                                    const std::string& reason, const std::string& robot_id) {
  job.state = state;
  job.updated_unix_ms = NowUnixMs();
  if (!reason.empty()) job.reason = reason;
  if (IsTerminal(state)) progress_decile_.erase(job.job_id);
  return jobs_->UpdateJob(job, MakeEvent(job, type, reason, robot_id)).status();
}

absl::Status JobService::Recover() {
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
  absl::MutexLock lock(&mutex_);
  storage::JobFilter in_flight;
  in_flight.states = {JobState::kAssigned, JobState::kRunning, JobState::kPaused};
  in_flight.page_size = params_.max_page_size;
  while (true) {
    ASSIGN_OR_RETURN(storage::JobPage page, jobs_->ListJobs(in_flight));
    for (Job& job : page.jobs) {
      if (job.state != JobState::kPaused) {
        RETURN_IF_ERROR(Transition(job, JobState::kPaused, JobEventType::kPaused,
                                   "server restarted; waiting for the robot to reconnect",
                                   job.assigned_robot_id));
      }
      lost_since_ns_[job.job_id] = clock_->NowNs();
      registry_->SetCurrentJob(job.assigned_robot_id, job.job_id);
      // Coordinated from where the robot reports when it is back; until then it holds the
      // others on its map (it may stand in their way).
      if (traffic_ != nullptr) {
        if (absl::StatusOr<JobAssignment> held = Resolve(job); held.ok()) {
          traffic_->Begin(job.assigned_robot_id, *held, TrafficCoordinator::kResumeWhereReported);
        }
      }
    }
    if (page.next_page_token.empty()) break;
    in_flight.page_token = page.next_page_token;
  }
  return absl::OkStatus();
}

absl::StatusOr<storage::CreatedJob> JobService::Submit(const SubmitJobRequest& request) {
  Job job;
  const bool has_route = !request.route_name.empty();
  if (has_route == request.goal.has_value()) {
    return absl::InvalidArgumentError("target: give either `route_name` or `goal`");
  }
  if (has_route) {
    ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredRoute> route,
                     site_->GetRoute(request.route_name, 0));
    job.route_name = route->route.name;
    job.route_version = route->version;
    job.map_id = route->route.map_id;
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
    job.map_id = request.goal_map_id;
    job.goal = request.goal;
  }
  if (!request.robot_id.empty()) RETURN_IF_ERROR(registry_->Get(request.robot_id).status());
  if (request.idempotency_key.size() > 128) {
    return absl::InvalidArgumentError("idempotency_key: at most 128 characters");
  }
  job.requested_robot_id = request.robot_id;
  job.priority = request.priority;
  job.idempotency_key = request.idempotency_key;
  job.on_robot_lost = request.on_robot_lost;
  job.created_unix_ms = job.updated_unix_ms = NowUnixMs();
  job.state = JobState::kQueued;
  absl::StatusOr<storage::CreatedJob> created =
      jobs_->CreateJob(job, MakeEvent(job, JobEventType::kQueued, "", ""));
  if (created.ok() && !created->deduplicated) WakeDispatcher();
  return created;
}

void JobService::WakeDispatcher() {
  absl::MutexLock lock(&work_mutex_);
  work_pending_ = true;
}

void JobService::WaitForWork(absl::Duration timeout) {
  absl::MutexLock lock(&work_mutex_);
  work_mutex_.AwaitWithTimeout(absl::Condition(&work_pending_), timeout);
  work_pending_ = false;
}

absl::StatusOr<Job> JobService::Get(const std::string& job_id) { return jobs_->GetJob(job_id); }

absl::StatusOr<storage::JobPage> JobService::List(storage::JobFilter filter) {
  if (filter.page_size == 0) filter.page_size = 100;
  if (filter.page_size < 0 || filter.page_size > params_.max_page_size) {
    return absl::InvalidArgumentError(absl::StrCat(
        "page_size: must be in [0, ", params_.max_page_size, "], got ", filter.page_size));
  }
  return jobs_->ListJobs(filter);
}

absl::StatusOr<Job> JobService::Cancel(const std::string& job_id, const std::string& reason) {
  absl::MutexLock lock(&mutex_);
  ASSIGN_OR_RETURN(Job job, jobs_->GetJob(job_id));
  if (IsTerminal(job.state)) {
    return absl::FailedPreconditionError(
        absl::StrCat("job '", job_id, "' has already ", std::string(JobStateName(job.state))));
  }
  const std::string robot = job.assigned_robot_id;
  const std::string why = reason.empty() ? "cancelled by operator" : reason;
  RETURN_IF_ERROR(Transition(job, JobState::kCancelled, JobEventType::kCancelled, why, robot));
  lost_since_ns_.erase(job_id);
  EndTraffic(job_id);
  if (!robot.empty()) {
    mailbox_->SendCommand(robot, JobCommand{JobCommandType::kCancel, job_id, why});
    registry_->SetCurrentJob(robot, "");
    WakeDispatcher();  // the robot is free for the next job
  }
  return job;
}

absl::StatusOr<Job> JobService::Pause(const std::string& job_id, const std::string& reason) {
  absl::MutexLock lock(&mutex_);
  ASSIGN_OR_RETURN(Job job, jobs_->GetJob(job_id));
  if (job.state != JobState::kAssigned && job.state != JobState::kRunning) {
    return absl::FailedPreconditionError(absl::StrCat("job '", job_id, "' is ",
                                                      std::string(JobStateName(job.state)),
                                                      "; only an assigned or running job pauses"));
  }
  const std::string why = reason.empty() ? "paused by operator" : reason;
  RETURN_IF_ERROR(
      Transition(job, JobState::kPaused, JobEventType::kPaused, why, job.assigned_robot_id));
  mailbox_->SendCommand(job.assigned_robot_id, JobCommand{JobCommandType::kPause, job_id, why});
  return job;
}

absl::StatusOr<Job> JobService::Resume(const std::string& job_id) {
  absl::MutexLock lock(&mutex_);
  ASSIGN_OR_RETURN(Job job, jobs_->GetJob(job_id));
  if (job.state != JobState::kPaused) {
    return absl::FailedPreconditionError(absl::StrCat(
        "job '", job_id, "' is ", std::string(JobStateName(job.state)), ", not paused"));
  }
  absl::StatusOr<RobotRecord> robot = registry_->Get(job.assigned_robot_id);
  if (!robot.ok() || robot->connection == ConnectionState::kOffline ||
      lost_since_ns_.count(job_id) > 0) {
    return absl::FailedPreconditionError(
        absl::StrCat("robot '", job.assigned_robot_id,
                     "' is offline; the job resumes when it reconnects with it"));
  }
  RETURN_IF_ERROR(Transition(job, JobState::kRunning, JobEventType::kResumed, "resumed by operator",
                             job.assigned_robot_id));
  mailbox_->SendCommand(job.assigned_robot_id,
                        JobCommand{JobCommandType::kResume, job_id, "resumed by operator"});
  return job;
}

absl::StatusOr<std::vector<JobEvent>> JobService::Events(const std::string& job_id,
                                                         int64_t after_sequence) {
  return jobs_->ListEvents(job_id, after_sequence);
}

void JobService::OnRobotConnected(const RobotIdentity& identity, const std::string& resume_job_id) {
  (void)robots_->UpsertRobot(storage::StoredRobot{identity.robot_id, identity.model.kind_name,
                                                  identity.capabilities, identity.software_version,
                                                  NowUnixMs()});
  absl::MutexLock lock(&mutex_);
  storage::JobFilter held;
  held.robot_id = identity.robot_id;
  held.states = {JobState::kPaused, JobState::kAssigned, JobState::kRunning};
  held.page_size = 10;
  absl::StatusOr<storage::JobPage> page = jobs_->ListJobs(held);
  if (!page.ok()) return;
  for (Job& job : page->jobs) {
    if (job.assigned_robot_id != identity.robot_id) continue;
    // A job an operator paused stays paused whatever the link did.
    const bool held_by_operator =
        job.state == JobState::kPaused && !lost_since_ns_.contains(job.job_id);
    lost_since_ns_.erase(job.job_id);
    if (job.job_id == resume_job_id) {
      if (held_by_operator) {
        mailbox_->SendCommand(identity.robot_id,
                              JobCommand{JobCommandType::kPause, job.job_id, job.reason});
      } else {
        (void)Transition(job, JobState::kRunning, JobEventType::kResumed, "robot reconnected",
                         identity.robot_id);
      }
      registry_->SetCurrentJob(identity.robot_id, job.job_id);
      if (traffic_ != nullptr) {
        if (traffic_->Tracks(job.job_id)) {
          traffic_->Resend(identity.robot_id);
        } else if (absl::StatusOr<JobAssignment> resumed = Resolve(job); resumed.ok()) {
          // The server restarted: coordinate the job again from where the robot reports.
          traffic_->Begin(identity.robot_id, *resumed, TrafficCoordinator::kResumeWhereReported);
        }
      }
    } else if (std::optional<RoutePosition> left_off = WhereRobotLeftOff(identity.robot_id, job);
               left_off && SendAgain(identity.robot_id, job, *left_off, held_by_operator)) {
      // Its agent restarted: the job goes on from where the robot stands.
    } else if (job.on_robot_lost == RequeuePolicy::kRequeue) {
      job.assigned_robot_id.clear();
      EndTraffic(job.job_id);
      (void)Transition(job, JobState::kQueued, JobEventType::kQueued,
                       "robot reconnected without the job; re-queued", identity.robot_id);
      registry_->SetCurrentJob(identity.robot_id, "");
    } else {
      EndTraffic(job.job_id);
      (void)Transition(job, JobState::kFailed, JobEventType::kFailed,
                       "robot reconnected without the job", identity.robot_id);
      registry_->SetCurrentJob(identity.robot_id, "");
    }
  }
  // The robot may still drive a job that ended or went elsewhere while it was away: it is told
  // before it can be handed another (its outbox delivers in order).
  if (!resume_job_id.empty()) CancelJobNoLongerHeld(identity.robot_id, resume_job_id);
}

std::optional<RoutePosition> JobService::WhereRobotLeftOff(const std::string& robot_id,
                                                           const Job& job) {
  absl::StatusOr<RobotRecord> record = registry_->Get(robot_id);
  if (!record.ok() || !record->last_telemetry || record->last_telemetry->job_id != job.job_id) {
    return std::nullopt;
  }
  const Telemetry& last = *record->last_telemetry;
  if (last.action_index < 0) return RoutePosition{};  // it had not begun
  return RoutePosition{last.action_index, last.action_progress_fraction};
}

bool JobService::SendAgain(const std::string& robot_id, Job& job, const RoutePosition& from,
                           bool held_by_operator) {
  absl::StatusOr<JobAssignment> assignment = Resolve(job);
  if (!assignment.ok() || !CheckRoutePosition(*assignment->route, from).ok()) return false;
  assignment->resume = from;
  if (!mailbox_->SendAssignment(robot_id, *assignment)) return false;
  const std::string why = absl::StrFormat(
      "robot came back without the job (its agent restarted): sent again from "
      "action %d, %.0f %% of it done",
      from.action_index, 100.0 * from.action_fraction);
  if (held_by_operator) {
    mailbox_->SendCommand(robot_id, JobCommand{JobCommandType::kPause, job.job_id, job.reason});
    (void)jobs_->UpdateJob(job, MakeEvent(job, JobEventType::kPaused, why, robot_id));
  } else {
    (void)Transition(job, JobState::kRunning, JobEventType::kResumed, why, robot_id);
  }
  registry_->SetCurrentJob(robot_id, job.job_id);
  if (traffic_ != nullptr) {
    if (traffic_->Tracks(job.job_id)) {
      traffic_->Resend(robot_id);
    } else {
      traffic_->Begin(robot_id, *assignment, TrafficCoordinator::kResumeWhereReported);
    }
  }
  return true;
}

void JobService::CancelJobNoLongerHeld(const std::string& robot_id, const std::string& job_id) {
  absl::StatusOr<Job> job = jobs_->GetJob(job_id);
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

void JobService::OnRobotDisconnected(const std::string& robot_id) {
  absl::MutexLock lock(&mutex_);
  absl::StatusOr<RobotRecord> record = registry_->Get(robot_id);
  if (!record.ok() || record->current_job_id.empty()) return;
  absl::StatusOr<Job> job = jobs_->GetJob(record->current_job_id);
  if (!job.ok() || IsTerminal(job->state) || job->state == JobState::kPaused) return;
  (void)Transition(*job, JobState::kPaused, JobEventType::kPaused, "robot disconnected", robot_id);
  lost_since_ns_[job->job_id] = clock_->NowNs();
}

void JobService::OnRobotEvent(const std::string& robot_id, const JobEvent& event) {
  absl::MutexLock lock(&mutex_);
  absl::StatusOr<Job> found = jobs_->GetJob(event.job_id);
  if (!found.ok() || found->assigned_robot_id != robot_id || IsTerminal(found->state)) return;
  Job job = *found;
  switch (event.type) {
    case JobEventType::kSucceeded:
      job.progress_fraction = 1.0;
      (void)Transition(job, JobState::kSucceeded, JobEventType::kSucceeded, event.reason, robot_id);
      registry_->SetCurrentJob(robot_id, "");
      WakeDispatcher();
      EndTraffic(job.job_id);
      UpdateTraffic();
      return;
    case JobEventType::kFailed:
      (void)Transition(job, JobState::kFailed, JobEventType::kFailed, event.reason, robot_id);
      registry_->SetCurrentJob(robot_id, "");
      WakeDispatcher();
      EndTraffic(job.job_id);
      UpdateTraffic();
      return;
    case JobEventType::kActionStarted:
    case JobEventType::kActionFinished:
    case JobEventType::kModeSwitch:
    case JobEventType::kBumper:
    case JobEventType::kLocalizationLost: {
      const bool starts = job.state == JobState::kAssigned;
      if (starts) job.state = JobState::kRunning;
      JobEvent stored =
          MakeEvent(job, starts ? JobEventType::kStarted : event.type, event.reason, robot_id);
      if (starts) (void)jobs_->UpdateJob(job, stored);
      stored = MakeEvent(job, event.type, event.reason, robot_id);
      stored.action_index = event.action_index;
      stored.mode = event.mode;
      (void)jobs_->UpdateJob(job, stored);
      if (event.type == JobEventType::kActionFinished && traffic_ != nullptr) {
        traffic_->OnActionFinished(robot_id, job.job_id, event.action_index);
        UpdateTraffic();
      }
      return;
    }
    default:
      return;
  }
}

void JobService::OnTelemetry(const std::string& robot_id, const Telemetry& telemetry) {
  if (telemetry.job_id.empty()) return;
  const int decile = static_cast<int>(std::floor(telemetry.job_progress_fraction * 10.0));
  absl::MutexLock lock(&mutex_);
  auto [it, inserted] = progress_decile_.try_emplace(telemetry.job_id, -1);
  if (decile <= it->second) return;  // progress is stored in steps of 10 %
  absl::StatusOr<Job> job = jobs_->GetJob(telemetry.job_id);
  if (!job.ok() || job->assigned_robot_id != robot_id || job->state != JobState::kRunning) return;
  it->second = decile;
  job->progress_fraction = std::clamp(telemetry.job_progress_fraction, 0.0, 1.0);
  job->updated_unix_ms = NowUnixMs();
  JobEvent event = MakeEvent(*job, JobEventType::kProgress, "", robot_id);
  event.action_index = telemetry.action_index;
  event.mode = telemetry.mode;
  (void)jobs_->UpdateJob(*job, event);
}

void JobService::HandleLostRobots() {
  const int64_t now_ns = clock_->NowNs();
  for (auto it = lost_since_ns_.begin(); it != lost_since_ns_.end();) {
    if ((now_ns - it->second) * 1e-9 < params_.lost_robot_timeout_s) {
      ++it;
      continue;
    }
    absl::StatusOr<Job> job = jobs_->GetJob(it->first);
    it = lost_since_ns_.erase(it);
    if (!job.ok() || job->state != JobState::kPaused) continue;
    const std::string robot = job->assigned_robot_id;
    registry_->SetCurrentJob(robot, "");
    EndTraffic(job->job_id);
    // The reason names the robot and how long it was away.
    const std::string lost =
        absl::StrCat("robot ", robot, " lost for ", params_.lost_robot_timeout_s, " s");
    if (job->on_robot_lost == RequeuePolicy::kRequeue) {
      job->assigned_robot_id.clear();
      (void)Transition(*job, JobState::kQueued, JobEventType::kQueued,
                       lost + "; re-queued by policy", robot);
    } else {
      (void)Transition(*job, JobState::kFailed, JobEventType::kFailed, lost, robot);
    }
  }
}

JobService::RouteFacts JobService::FactsOf(const Job& job) {
  if (job.goal) return RouteFacts{{"free_navigation"}, job.goal->translation()};
  const auto key = std::make_pair(job.route_name, job.route_version);
  auto known = route_facts_.find(key);
  if (known != route_facts_.end()) return known->second;
  RouteFacts facts;
  absl::StatusOr<std::shared_ptr<const storage::StoredRoute>> route =
      site_->GetRoute(job.route_name, job.route_version);
  if (route.ok()) {
    std::set<std::string> needed;
    for (const RouteAction& action : (*route)->route.actions) {
      needed.insert(std::string(ActionTypeName(action.params)));
      const auto* nav = std::get_if<FreeNavigationAction>(&action.params);
      if (nav != nullptr && !facts.start) {
        facts.start = nav->waypoints_m.empty() ? nav->goal.translation() : nav->waypoints_m.front();
      }
    }
    facts.needed.assign(needed.begin(), needed.end());
  }
  return route_facts_.emplace(key, std::move(facts)).first->second;
}

absl::StatusOr<JobAssignment> JobService::Resolve(const Job& job) {
  JobAssignment assignment;
  assignment.job = job;
  if (!job.route_name.empty()) {
    ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredRoute> route,
                     site_->GetRoute(job.route_name, job.route_version));
    assignment.route = std::shared_ptr<const Route>(route, &route->route);
    assignment.route_version = route->version;
  } else if (job.goal) {
    // A go-to-goal job is a route of one free-navigation action.
    auto goal_route = std::make_shared<Route>();
    goal_route->name = "goal";
    goal_route->map_id = job.map_id;
    FreeNavigationAction go;
    go.goal = *job.goal;
    goal_route->actions.push_back({go, {EndConditionKind::kGoalReached}});
    assignment.route = std::move(goal_route);
  }
  ASSIGN_OR_RETURN(assignment.map_version, site_data_->LatestMapVersion(job.map_id));
  assignment.marker_set_version = site_data_->LatestMarkerSetVersion(job.map_id);
  return assignment;
}

absl::Status JobService::ForgetRobot(const std::string& robot_id) {
  absl::MutexLock lock(&mutex_);
  return ForgetRobotLocked(robot_id);
}

absl::Status JobService::ForgetRobotLocked(const std::string& robot_id) {
  // The registry refuses a connected robot or one with a job; the store follows it.
  RETURN_IF_ERROR(registry_->Forget(robot_id));
  robot_map_.erase(robot_id);
  charging_job_.erase(robot_id);
  absl::Status stored = robots_->DeleteRobot(robot_id);
  return absl::IsNotFound(stored) ? absl::OkStatus() : stored;
}

int JobService::DispatchOnce() {
  absl::MutexLock lock(&mutex_);
  HandleLostRobots();
  if (params_.evict_offline_robots_after_s > 0.0) {
    for (const std::string& robot_id :
         registry_->OfflineLongerThan(params_.evict_offline_robots_after_s)) {
      (void)ForgetRobotLocked(robot_id);
    }
  }
  SendLowRobotsToCharge();
  const int assigned = AssignQueued();
  UpdateTraffic();
  return assigned;
}

void JobService::SayWhyQueued(Job& job, const std::vector<std::string>& needed,
                              const std::set<std::string>& online_capabilities) {
  std::string why;
  if (!job.requested_robot_id.empty()) {
    const std::string& id = job.requested_robot_id;
    absl::StatusOr<RobotRecord> robot = registry_->Get(id);
    if (!robot.ok()) {
      why = absl::StrCat("robot ", id, " is not known");
    } else if (robot->connection != ConnectionState::kOnline) {
      why = absl::StrCat(
          "robot ", id, " is ",
          robot->connection == ConnectionState::kStale ? "not reporting (stale)" : "offline");
    } else {
      for (const std::string& capability : needed) {
        const auto& have = robot->identity.capabilities;
        if (std::find(have.begin(), have.end(), capability) == have.end()) {
          why = absl::StrCat("robot ", id, " cannot run ", capability);
          break;
        }
      }
      if (why.empty() && !robot->current_job_id.empty()) {
        why = absl::StrCat("waits for robot ", id, " to finish job ", robot->current_job_id);
      } else if (why.empty()) {
        why = absl::StrCat("robot ", id,
                           charging_job_.contains(id) ? " is kept for charging" : " is not free");
      }
    }
  } else {
    for (const std::string& capability : needed) {
      if (!online_capabilities.contains(capability)) {
        why = absl::StrCat("no connected robot can run ", capability);
        break;
      }
    }
    if (why.empty()) why = "every connected robot that can run it is busy or charging";
  }
  if (why == job.reason) return;
  job.reason = why;
  (void)jobs_->UpdateJob(job, MakeEvent(job, JobEventType::kQueued, why, ""));
}

bool JobService::HeldForCharging(const RobotRecord& robot) {
  auto it = charging_job_.find(robot.identity.robot_id);
  if (it == charging_job_.end()) return false;
  absl::StatusOr<Job> job = jobs_->GetJob(it->second);
  const bool charged =
      robot.last_telemetry && robot.last_telemetry->battery_fraction >= params_.charged_fraction;
  if (!job.ok() || job->state == JobState::kFailed || job->state == JobState::kCancelled ||
      (job->state == JobState::kSucceeded && charged)) {
    charging_job_.erase(it);  // charged, or sent again on the next pass
    return false;
  }
  return true;
}

void JobService::SendLowRobotsToCharge() {
  if (params_.charge_below_fraction <= 0.0 || params_.charging_routes.empty()) return;
  const std::vector<RobotRecord> low = registry_->IdleOnline([&](const RobotRecord& r) {
    return r.last_telemetry && r.last_telemetry->battery_fraction < params_.charge_below_fraction;
  });
  for (const RobotRecord& robot : low) {
    if (HeldForCharging(robot)) continue;
    const std::string& id = robot.identity.robot_id;
    std::string route;
    if (auto map = robot_map_.find(id); map != robot_map_.end()) {
      if (auto r = params_.charging_routes.find(map->second); r != params_.charging_routes.end()) {
        route = r->second;
      }
    } else if (params_.charging_routes.size() == 1) {
      route = params_.charging_routes.begin()->second;
    }
    if (route.empty()) continue;  // no charger known for where it is
    SubmitJobRequest request;
    request.route_name = route;
    request.robot_id = id;
    request.priority = std::numeric_limits<int>::max();
    request.idempotency_key = absl::StrCat("charge/", id, "/", NowUnixMs());
    absl::StatusOr<storage::CreatedJob> created = Submit(request);
    if (created.ok()) charging_job_[id] = created->job.job_id;
  }
}

int JobService::AssignQueued() {
  storage::JobFilter queued_filter;
  queued_filter.states = {JobState::kQueued};
  queued_filter.page_size = params_.max_page_size;
  absl::StatusOr<storage::JobPage> page = jobs_->ListJobs(queued_filter);
  if (!page.ok() || page->jobs.empty()) return 0;
  std::vector<Job> queued = page->jobs;
  std::stable_sort(queued.begin(), queued.end(), [](const Job& a, const Job& b) {
    return a.priority != b.priority ? a.priority > b.priority
                                    : a.created_unix_ms < b.created_unix_ms;
  });
  std::vector<RouteFacts> job_facts;
  job_facts.reserve(queued.size());
  for (const Job& job : queued) job_facts.push_back(FactsOf(job));
  // What the queued jobs ask for: a robot (or any) with capabilities. Only robots that can serve
  // one of these demands are copied out of the registry, so jobs no robot can drive cost nothing
  // per robot, however large the fleet.
  using Demand = std::pair<std::string, const std::vector<std::string>*>;
  auto fits = [](const std::vector<std::string>& have, const std::vector<std::string>& needed) {
    return std::all_of(needed.begin(), needed.end(), [&](const std::string& c) {
      return std::find(have.begin(), have.end(), c) != have.end();
    });
  };
  std::vector<Demand> demands;
  for (size_t j = 0; j < queued.size(); ++j) {
    Demand demand{queued[j].requested_robot_id, &job_facts[j].needed};
    const bool seen = std::any_of(demands.begin(), demands.end(), [&](const Demand& d) {
      return d.first == demand.first && *d.second == *demand.second;
    });
    if (!seen) demands.push_back(demand);
  }
  std::vector<RobotRecord> idle = registry_->IdleOnline([&](const RobotRecord& record) {
    return std::any_of(demands.begin(), demands.end(), [&](const Demand& d) {
      return (d.first.empty() || d.first == record.identity.robot_id) &&
             fits(record.identity.capabilities, *d.second);
    });
  });
  // A demand that found no robot finds none later in this pass either: idle robots only leave.
  std::vector<Demand> unmet;
  std::optional<std::set<std::string>> online_capabilities;  // read once, when a job waits
  int assigned = 0;
  for (size_t j = 0; j < queued.size(); ++j) {
    Job& job = queued[j];
    const std::vector<std::string>& needed = job_facts[j].needed;
    const std::optional<Eigen::Vector2d> start = job_facts[j].start;
    const bool known_unmet = std::any_of(unmet.begin(), unmet.end(), [&](const Demand& d) {
      return d.first == job.requested_robot_id && *d.second == needed;
    });
    if (known_unmet || idle.empty()) {
      if (!online_capabilities) online_capabilities = registry_->OnlineCapabilities();
      SayWhyQueued(job, needed, *online_capabilities);
      continue;
    }
    auto best = idle.end();
    double best_distance_m = std::numeric_limits<double>::infinity();
    for (auto it = idle.begin(); it != idle.end(); ++it) {
      if (!job.requested_robot_id.empty() && it->identity.robot_id != job.requested_robot_id) {
        continue;
      }
      if (!fits(it->identity.capabilities, needed)) continue;
      // A robot kept for charging takes its charging job only.
      if (HeldForCharging(*it) && charging_job_.at(it->identity.robot_id) != job.job_id) continue;
      double distance_m = 0.0;
      if (start && it->last_telemetry) {
        const Eigen::Vector2d here = it->last_telemetry->pose_in_map.translation();
        const std::optional<double> path_m = travel_.Between(job.map_id, here, *start);
        // No path known (off the map, walled off): ranked after every robot with one.
        distance_m = path_m ? *path_m : kNoPathRankM + (here - *start).norm();
      }
      if (distance_m < best_distance_m) {
        best_distance_m = distance_m;
        best = it;
      }
    }
    if (best == idle.end()) {
      unmet.emplace_back(job.requested_robot_id, &needed);
      if (!online_capabilities) online_capabilities = registry_->OnlineCapabilities();
      SayWhyQueued(job, needed, *online_capabilities);
      continue;
    }
    const std::string robot = best->identity.robot_id;
    job.assigned_robot_id = robot;
    robot_map_[robot] = job.map_id;
    if (!Transition(job, JobState::kAssigned, JobEventType::kAssigned, "", robot).ok()) continue;
    absl::StatusOr<JobAssignment> assignment = Resolve(job);
    if (!assignment.ok() || !mailbox_->SendAssignment(robot, *assignment)) {
      job.assigned_robot_id.clear();
      (void)Transition(job, JobState::kQueued, JobEventType::kQueued,
                       assignment.ok() ? "robot unreachable; re-queued"
                                       : std::string(assignment.status().message()),
                       robot);
      continue;
    }
    registry_->SetCurrentJob(robot, job.job_id);
    if (traffic_ != nullptr) traffic_->Begin(robot, *assignment);
    idle.erase(best);
    ++assigned;
  }
  return assigned;
}

}  // namespace fleetnav::server
