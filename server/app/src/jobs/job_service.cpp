#include "fleetnav/server/jobs/job_service.hpp"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::server {

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
    : robots_(robots),
      registry_(registry),
      params_(std::move(params)),
      ledger_(jobs, clock),
      traffic_(traffic, &ledger_),
      recovery_(&ledger_, robots, registry, mailbox, &traffic_, site, site_data, clock,
                JobRecoveryParams{params_.lost_robot_timeout_s, params_.max_page_size}),
      lifecycle_(&ledger_, site, site_data, registry, mailbox, &traffic_, &recovery_, &work_),
      matcher_(&ledger_, &lifecycle_, registry, mailbox, &traffic_, site, site_data,
               MatcherParams()) {}

JobMatcherParams JobService::MatcherParams() const {
  return JobMatcherParams{params_.max_page_size, params_.charge_below_fraction,
                          params_.charged_fraction, params_.charging_routes};
}

absl::Status JobService::Recover() {
  absl::MutexLock lock(&mutex_);
  return recovery_.RestoreAfterRestart();
}

absl::StatusOr<storage::CreatedJob> JobService::Submit(const SubmitJobRequest& request) {
  absl::MutexLock lock(&mutex_);
  return lifecycle_.Submit(request);
}

absl::StatusOr<Job> JobService::Get(const std::string& job_id) { return ledger_.Get(job_id); }

absl::StatusOr<storage::JobPage> JobService::List(storage::JobFilter filter) {
  if (filter.page_size == 0) filter.page_size = 100;
  if (filter.page_size < 0 || filter.page_size > params_.max_page_size) {
    return absl::InvalidArgumentError(absl::StrCat(
        "page_size: must be in [0, ", params_.max_page_size, "], got ", filter.page_size));
  }
  return ledger_.List(filter);
}

absl::StatusOr<Job> JobService::Cancel(const std::string& job_id, const std::string& reason) {
  absl::MutexLock lock(&mutex_);
  return lifecycle_.Cancel(job_id, reason);
}

absl::StatusOr<Job> JobService::Pause(const std::string& job_id, const std::string& reason) {
  absl::MutexLock lock(&mutex_);
  return lifecycle_.Pause(job_id, reason);
}

absl::StatusOr<Job> JobService::Resume(const std::string& job_id) {
  absl::MutexLock lock(&mutex_);
  return lifecycle_.Resume(job_id);
}

absl::StatusOr<std::vector<JobEvent>> JobService::Events(const std::string& job_id,
                                                         int64_t after_sequence) {
  return ledger_.Events(job_id, after_sequence);
}

void JobService::OnRobotConnected(const RobotIdentity& identity, const std::string& resume_job_id) {
  absl::MutexLock lock(&mutex_);
  recovery_.OnRobotConnected(identity, resume_job_id);
}

void JobService::OnRobotDisconnected(const std::string& robot_id) {
  absl::MutexLock lock(&mutex_);
  recovery_.OnRobotDisconnected(robot_id);
}

void JobService::OnRobotEvent(const std::string& robot_id, const JobEvent& event) {
  absl::MutexLock lock(&mutex_);
  lifecycle_.OnRobotEvent(robot_id, event);
  if (event.type == JobEventType::kSucceeded) matcher_.OnJobSucceeded(robot_id, event.job_id);
}

void JobService::OnTelemetry(const std::string& robot_id, const Telemetry& telemetry) {
  // Most telemetry reaches no new 10 % step: it is let go without JobService's lock, which the
  // dispatcher and the job's writers hold.
  if (telemetry.job_id.empty() ||
      !ledger_.IsNewProgressStep(telemetry.job_id, telemetry.job_progress_fraction)) {
    return;
  }
  absl::MutexLock lock(&mutex_);
  lifecycle_.OnTelemetry(robot_id, telemetry);
}

absl::Status JobService::ForgetRobot(const std::string& robot_id) {
  absl::MutexLock lock(&mutex_);
  return ForgetRobotLocked(robot_id);
}

absl::Status JobService::ForgetRobotLocked(const std::string& robot_id) {
  // The registry refuses a connected robot or one with a job; the store follows it.
  RETURN_IF_ERROR(registry_->Forget(robot_id));
  matcher_.ForgetRobot(robot_id);
  absl::Status stored = robots_->DeleteRobot(robot_id);
  return absl::IsNotFound(stored) ? absl::OkStatus() : stored;
}

void JobService::WaitForWork(absl::Duration timeout) { work_.WaitFor(timeout); }

bool JobService::TakeWork() { return work_.Take(); }

void JobService::WakeDispatcher() { work_.Notify(); }

int JobService::DispatchOnce() {
  absl::MutexLock lock(&mutex_);
  recovery_.ExpireLostRobots();
  if (params_.evict_offline_robots_after_s > 0.0) {
    for (const std::string& robot_id :
         registry_->OfflineLongerThan(params_.evict_offline_robots_after_s)) {
      (void)ForgetRobotLocked(robot_id);
    }
  }
  matcher_.SendLowRobotsToCharge();
  const int assigned = matcher_.AssignQueued();
  traffic_.Update();
  // Robots in a waiting robot's way go aside (a held job they have not started is queued
  // again first); the make-way jobs are given on the next pass, before anything else.
  std::vector<MakeWayRequest> make_way = traffic_.TakeMakeWayRequests();
  std::erase_if(make_way, [&](const MakeWayRequest& request) {
    if (request.withdraw_job_id.empty()) return false;
    const bool make_way_job = matcher_.IsMakeWayJob(request.withdraw_job_id);
    if (!matcher_.WouldSendToMakeWay(request, make_way_job ? request.withdraw_job_id : "")) {
      return true;  // it would not go aside: its job stays
    }
    if (make_way_job) {
      // A make-way job is not withdrawn (that would queue the same move again), but one in a
      // circle of waits is given up for a place off the ways as they are now.
      return !request.breaks_wait_cycle ||
             !lifecycle_
                  .Cancel(request.withdraw_job_id,
                          absl::StrCat("its way closes a circle of waits (", request.for_robot_id,
                                       " waits for ", request.robot_id, "); sent to another place"))
                  .ok();
    }
    return !lifecycle_
                .Withdraw(request.withdraw_job_id,
                          absl::StrCat("withdrawn from ", request.robot_id, " to let ",
                                       request.for_robot_id, " pass",
                                       request.breaks_wait_cycle ? " (a circle of waits)" : "",
                                       "; queued again"))
                .ok();
  });
  if (!make_way.empty()) {
    matcher_.SendToMakeWay(make_way);
    work_.Notify();
  }
  return assigned;
}

}  // namespace fleetnav::server
