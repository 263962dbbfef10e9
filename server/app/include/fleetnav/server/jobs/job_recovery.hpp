#pragma once

#include <map>
#include <optional>
#include <string>

#include "absl/status/status.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/job.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/server/jobs/job_ledger.hpp"
#include "fleetnav/server/jobs/job_traffic.hpp"
#include "fleetnav/server/robots/fleet_registry.hpp"
#include "fleetnav/server/robots/robot_mailbox.hpp"
#include "fleetnav/storage/robot_repository.hpp"

namespace fleetnav::server {

struct JobRecoveryParams {
  /// A paused job whose robot stays away this long is failed or re-queued by its policy.
  double lost_robot_timeout_s = 30.0;
  int max_page_size = 1000;
};

/// Jobs across absences: a robot that drops holds its job paused; one that comes back with the
/// job resumes it, one whose agent restarted without it is sent it again from where it stands
/// (no action begun anew), and after lost_robot_timeout_s the job is failed or re-queued by its
/// policy. After a server restart, robots are restored offline and every job in flight waits
/// paused for its robot. A job an operator paused stays paused whatever the link did. Not
/// thread-safe: JobService serialises its callers.
class JobRecovery {
 public:
  JobRecovery(JobLedger* ledger, storage::RobotRepository* robots, FleetRegistry* registry,
              RobotMailbox* mailbox, JobTraffic* traffic, SiteCatalog* site, SiteCache* site_data,
              const Clock* clock, JobRecoveryParams params)
      : ledger_(ledger),
        robots_(robots),
        registry_(registry),
        mailbox_(mailbox),
        traffic_(traffic),
        site_(site),
        site_data_(site_data),
        clock_(clock),
        params_(params) {}

  /// Restores robots (offline) and pauses jobs that were assigned or running when the server
  /// stopped. Call once before serving.
  absl::Status RestoreAfterRestart();
  void OnRobotConnected(const RobotIdentity& identity, const std::string& resume_job_id);
  void OnRobotDisconnected(const std::string& robot_id);
  /// Fails or re-queues the jobs whose robot has been away longer than the timeout.
  void ExpireLostRobots();
  /// Whether `job_id` is paused because its robot is away (not by an operator).
  bool IsAway(const std::string& job_id) const { return away_since_ns_.contains(job_id); }
  /// Forgets a job that ended while its robot was away.
  void Forget(const std::string& job_id) { away_since_ns_.erase(job_id); }

 private:
  /// Where the robot's last telemetry placed it in `job` (nullopt: it never reported the job).
  std::optional<RoutePosition> WhereRobotLeftOff(const std::string& robot_id, const Job& job);
  /// Sends `job` again to its robot, whose agent came back without it, to begin at `from`; the
  /// job runs again (or stays paused when an operator paused it) and keeps its traffic place.
  /// False when it cannot be sent.
  bool SendAgain(const std::string& robot_id, Job& job, const RoutePosition& from,
                 bool held_by_operator);
  /// Sends CANCEL with the reason when `job_id` is no longer the robot's running job.
  void CancelJobNoLongerHeld(const std::string& robot_id, const std::string& job_id);

  JobLedger* ledger_;
  storage::RobotRepository* robots_;
  FleetRegistry* registry_;
  RobotMailbox* mailbox_;
  JobTraffic* traffic_;
  SiteCatalog* site_;
  SiteCache* site_data_;
  const Clock* clock_;
  JobRecoveryParams params_;
  std::map<std::string, int64_t> away_since_ns_;  ///< by job id
};

}  // namespace fleetnav::server
