#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/job.hpp"
#include "fleetnav/server/jobs/job_ledger.hpp"
#include "fleetnav/server/jobs/job_lifecycle.hpp"
#include "fleetnav/server/jobs/job_matcher.hpp"
#include "fleetnav/server/jobs/job_recovery.hpp"
#include "fleetnav/server/jobs/job_traffic.hpp"
#include "fleetnav/server/jobs/work_signal.hpp"
#include "fleetnav/server/robots/fleet_registry.hpp"
#include "fleetnav/server/robots/robot_mailbox.hpp"
#include "fleetnav/server/site/site_cache.hpp"
#include "fleetnav/server/site/site_catalog.hpp"
#include "fleetnav/server/traffic/traffic_coordinator.hpp"
#include "fleetnav/storage/job_repository.hpp"
#include "fleetnav/storage/robot_repository.hpp"

namespace fleetnav::server {

struct JobServiceParams {
  /// A paused job whose robot stays away this long is failed or re-queued by its policy.
  double lost_robot_timeout_s = 30.0;
  /// A robot offline this long that holds no job is forgotten (registry and store); 0: never.
  double evict_offline_robots_after_s = 86400.0;
  int max_page_size = 1000;
  /// A robot whose battery falls below this fraction gets no more work: it is sent to its
  /// charger (charging_routes) and stays there until charged to charged_fraction (0: never).
  double charge_below_fraction = 0.2;
  double charged_fraction = 0.9;
  /// The route that takes a robot to its charger, by map id (the map of the robot's last job;
  /// the only route when there is one).
  std::map<std::string, std::string> charging_routes;
  absl::Status Validate() const;
};

/// The job services behind one lock: a job's life (JobLifecycle), its survival across robot
/// and server restarts (JobRecovery) and the choice of robot (JobMatcher), with traffic
/// coordination (JobTraffic) when a TrafficCoordinator is given. Every transition is stored with
/// its event before anyone is told. Thread-safe: calls are serialised by one mutex, so the
/// parts need none of their own.
class JobService {
 public:
  JobService(storage::JobRepository* jobs, storage::RobotRepository* robots, SiteCache* site_data,
             SiteCatalog* site, FleetRegistry* registry, RobotMailbox* mailbox, const Clock* clock,
             JobServiceParams params, TrafficCoordinator* traffic = nullptr);

  /// Restores robots (offline) and pauses jobs that were assigned or running when the server
  /// stopped. Call once before serving.
  absl::Status Recover();

  absl::StatusOr<storage::CreatedJob> Submit(const SubmitJobRequest& request);
  absl::StatusOr<Job> Get(const std::string& job_id);
  absl::StatusOr<storage::JobPage> List(storage::JobFilter filter);
  /// FailedPrecondition for a job that has already ended.
  absl::StatusOr<Job> Cancel(const std::string& job_id, const std::string& reason);
  /// Operator pause of an assigned or running job: the robot is told to stop where it is and
  /// keeps its place in traffic. FailedPrecondition for a job in another state.
  absl::StatusOr<Job> Pause(const std::string& job_id, const std::string& reason);
  /// Lets a job paused by Pause go on. FailedPrecondition for a job that is not paused or whose
  /// robot is not online (it resumes when the robot reconnects with it).
  absl::StatusOr<Job> Resume(const std::string& job_id);
  absl::StatusOr<std::vector<JobEvent>> Events(const std::string& job_id, int64_t after_sequence);

  void OnRobotConnected(const RobotIdentity& identity, const std::string& resume_job_id);
  void OnRobotDisconnected(const std::string& robot_id);
  /// A job event a robot reports (action started/finished, succeeded, failed, mode switch).
  void OnRobotEvent(const std::string& robot_id, const JobEvent& event);
  void OnTelemetry(const std::string& robot_id, const Telemetry& telemetry);

  /// Removes an offline robot that holds no job from the registry and the store: NotFound for
  /// an unknown robot, FailedPrecondition for one that is connected or holds a job.
  absl::Status ForgetRobot(const std::string& robot_id);

  /// Blocks until there may be work for the dispatcher (a job submitted or cancelled, a robot
  /// connected, a job ended, WakeDispatcher) or `timeout` passed, so that a job is dispatched
  /// when it can be rather than at the next period.
  void WaitForWork(absl::Duration timeout);
  /// Whether there may be work since the last wait or take (a lockstep tick asks, not waits).
  bool TakeWork();
  void WakeDispatcher();

  /// One dispatcher pass: lost-robot timeouts, evictions, assignments, then traffic clearances.
  /// Returns jobs assigned.
  int DispatchOnce();

 private:
  JobMatcherParams MatcherParams() const;
  absl::Status ForgetRobotLocked(const std::string& robot_id) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  storage::RobotRepository* robots_;
  FleetRegistry* registry_;
  JobServiceParams params_;
  absl::Mutex mutex_;
  JobLedger ledger_;  ///< its reads are thread-safe; its writes happen under mutex_
  JobTraffic traffic_ ABSL_GUARDED_BY(mutex_);
  JobRecovery recovery_ ABSL_GUARDED_BY(mutex_);
  WorkSignal work_;
  JobLifecycle lifecycle_ ABSL_GUARDED_BY(mutex_);
  JobMatcher matcher_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav::server
