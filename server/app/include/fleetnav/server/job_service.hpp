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
#include "fleetnav/server/fleet_registry.hpp"
#include "fleetnav/server/robot_mailbox.hpp"
#include "fleetnav/server/site_cache.hpp"
#include "fleetnav/server/site_catalog.hpp"
#include "fleetnav/server/traffic_coordinator.hpp"
#include "fleetnav/server/travel_distances.hpp"
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

struct SubmitJobRequest {
  std::string route_name;   ///< either a route …
  std::string goal_map_id;  ///< … or a goal on a map
  std::optional<Pose2> goal;
  std::string robot_id;  ///< empty: any capable robot
  int priority = 0;
  std::string idempotency_key;
  RequeuePolicy on_robot_lost = RequeuePolicy::kFail;
};

/// Jobs from submission to their end, and the dispatcher. Every transition is stored with its
/// event (JobRepository) before anyone is told. Dispatch (DispatchOnce): queued jobs in order of
/// priority (high first) then age go to connected, idle robots whose capabilities include every
/// action type of the route (go-to-goal jobs need "free_navigation"), the robot with the
/// shortest path over the map (TravelDistances) to the job's first known point first. A robot
/// whose battery is low is sent to its charger first and given nothing else until charged. A robot
/// that drops holds its job paused; when it returns with the job it resumes, and after
/// lost_robot_timeout_s the job is failed or re-queued by its policy. With a TrafficCoordinator
/// every running job is coordinated (traffic clearances, waits recorded as WAITING_FOR_TRAFFIC
/// events). Thread-safe: transitions are serialised by one mutex.
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
  void WakeDispatcher();

  /// One dispatcher pass: lost-robot timeouts, evictions, assignments, then traffic clearances.
  /// Returns jobs assigned.
  int DispatchOnce();

 private:
  absl::Status Transition(Job& job, JobState state, JobEventType type, const std::string& reason,
                          const std::string& robot_id) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// What dispatching needs to know of a job's route: the action types it needs and its
  /// first known point.
  struct RouteFacts {
    std::vector<std::string> needed;
    std::optional<Eigen::Vector2d> start;
  };
  absl::StatusOr<JobAssignment> Resolve(const Job& job);
  /// A route's facts are kept by (route, version), which never changes, so a queued job costs
  /// nothing per pass however long its route.
  RouteFacts FactsOf(const Job& job) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void HandleLostRobots() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  absl::Status ForgetRobotLocked(const std::string& robot_id) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Where the robot's last telemetry placed it in `job` (nullopt: it never reported the job).
  std::optional<RoutePosition> WhereRobotLeftOff(const std::string& robot_id, const Job& job)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Sends `job` again to its robot, whose agent came back without it, to begin at `from`; the
  /// job runs again (or stays paused when an operator paused it) and keeps its traffic place.
  /// False when it cannot be sent.
  bool SendAgain(const std::string& robot_id, Job& job, const RoutePosition& from,
                 bool held_by_operator) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Sends CANCEL with the reason when `job_id` is no longer the robot's running job.
  void CancelJobNoLongerHeld(const std::string& robot_id, const std::string& job_id)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  int AssignQueued() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Stores why `job` stays queued (one QUEUED event when the reason changes): "no connected
  /// robot can run stripe_navigation", "robot lely2 is offline", "waits for robot lely2 to
  /// finish job job-000004", ….
  void SayWhyQueued(Job& job, const std::vector<std::string>& needed,
                    const std::set<std::string>& online_capabilities)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Submits a charging job for each idle robot whose battery is low and that is not charging.
  void SendLowRobotsToCharge() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Whether `robot` is kept for charging: its charging job runs, or it charges after it.
  bool HeldForCharging(const RobotRecord& robot) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Decides traffic clearances and stores a waiting event for each job whose wait changed.
  void UpdateTraffic() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void EndTraffic(const std::string& job_id);

  storage::JobRepository* jobs_;
  storage::RobotRepository* robots_;
  SiteCache* site_data_;
  SiteCatalog* site_;
  FleetRegistry* registry_;
  RobotMailbox* mailbox_;
  const Clock* clock_;
  JobServiceParams params_;
  TrafficCoordinator* traffic_;  ///< null: robots are not coordinated
  absl::Mutex mutex_;
  std::map<std::string, int64_t> lost_since_ns_ ABSL_GUARDED_BY(mutex_);  ///< by job id
  std::map<std::string, int> progress_decile_ ABSL_GUARDED_BY(mutex_);    ///< by job id
  std::map<std::pair<std::string, uint32_t>, RouteFacts> route_facts_ ABSL_GUARDED_BY(mutex_);
  TravelDistances travel_ ABSL_GUARDED_BY(mutex_);
  std::map<std::string, std::string> robot_map_ ABSL_GUARDED_BY(mutex_);     ///< last job's map
  std::map<std::string, std::string> charging_job_ ABSL_GUARDED_BY(mutex_);  ///< by robot id
  absl::Mutex work_mutex_;
  bool work_pending_ ABSL_GUARDED_BY(work_mutex_) = false;
};

}  // namespace fleetnav::server
