#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "absl/status/status.h"
#include "absl/synchronization/mutex.h"
#include "absl/synchronization/notification.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/server/access/access_control.hpp"
#include "fleetnav/server/access/operator_tokens.hpp"
#include "fleetnav/server/jobs/dispatcher_loop.hpp"
#include "fleetnav/server/jobs/job_service.hpp"
#include "fleetnav/server/jobs/notifying_job_repository.hpp"
#include "fleetnav/server/robot_sessions.hpp"
#include "fleetnav/server/robots/fleet_registry.hpp"
#include "fleetnav/server/robots/pose_history_recorder.hpp"
#include "fleetnav/server/robots/robot_mailbox.hpp"
#include "fleetnav/server/site/input_limits.hpp"
#include "fleetnav/server/site/map_catalog.hpp"
#include "fleetnav/server/site/site_cache.hpp"
#include "fleetnav/server/site/site_catalog.hpp"
#include "fleetnav/server/site/stop_control.hpp"
#include "fleetnav/server/site/zone_catalog.hpp"
#include "fleetnav/server/traffic/traffic_coordinator.hpp"
#include "fleetnav/server/traffic/traffic_planner.hpp"
#include "fleetnav/storage/postgres/pg_database.hpp"
#include "fleetnav/storage/sql/sql_database.hpp"
#include "fleetnav/storage/sql/sql_fleet_repositories.hpp"
#include "fleetnav/storage/sql/sql_map_repository.hpp"

namespace fleetnav::server {

struct FleetAppParams {
  /// An SQLite file, created if missing, or a postgresql:// URI (storage::OpenFleetDatabase).
  std::string db_path = "fleetnav.db";
  /// How a PostgreSQL store is reached (waits at start and on reconnection).
  storage::PgOpenOptions postgres;
  FleetRegistryParams registry;
  JobServiceParams jobs;
  TrafficCoordinatorParams traffic;
  PoseHistoryParams pose_history;
  SiteCacheParams site_cache;
  InputLimits limits;
  double dispatch_period_s = 0.2;  ///< how often queued jobs are matched to idle robots
  /// Whether callers are authorized (a TLS server): then access() applies the tokens of
  /// `file_tokens` and the store.
  bool authorize = false;
  std::vector<OperatorToken> file_tokens;
  /// Told about every refused call (method, caller and reason), for the log.
  std::function<void(const std::string&)> on_access_refused;
  /// Told about every job event stored (state changes and progress), for the log. Quick.
  std::function<void(const Job&, const JobEvent&)> on_job_event;
  /// Told about every job or job event stored, by job id (the watch streams). Quick.
  std::function<void(const std::string& job_id)> on_job_changed;
  /// Told about operator tokens created and revoked, and stored ones the token file overrides,
  /// for the log (never a secret).
  std::function<void(const std::string&)> on_token_change;
  /// Told each store transaction's and each assigning dispatch pass's duration (metrics).
  std::function<void(double seconds)> on_store_transaction;
  std::function<void(double seconds)> on_dispatch_pass;
  absl::Status Validate() const;
};

/// fleetnavd's use cases assembled, with no transport: opens the store, owns the repositories,
/// the site catalogs, the robot registry and sessions, traffic coordination, the job service,
/// operator tokens and access control, and runs the two loops of the server: the dispatcher
/// (on a thread of its own, or at each tick in lockstep) and the housekeeping (stale robots and
/// pose history, due by the injected clock; memory returned to the system). The gRPC server
/// (rpc/FleetServer), the HTTP port and replicas are edges built over it. Open once, then Start;
/// Stop ends the loops.
class FleetApp {
 public:
  /// `clock` (the system's or the simulator's) and `robots` (the transport's mailbox) outlive
  /// the app.
  FleetApp(FleetAppParams params, const Clock* clock, RobotMailbox* robots);
  ~FleetApp();
  FleetApp(const FleetApp&) = delete;
  FleetApp& operator=(const FleetApp&) = delete;

  /// Opens the store, loads the operator tokens, recovers robots and unfinished jobs. Nothing
  /// runs yet.
  absl::Status Open();
  /// Starts the dispatcher and housekeeping loops. While `ticks_keep_house` says so (a
  /// simulated run in lockstep), the ticks keep house instead of the loop.
  void Start(std::function<bool()> ticks_keep_house = {});
  void Stop();
  /// A simulated run's first robot joined in lockstep: from now on only RunTick dispatches.
  void EnterLockstep();
  /// One lockstep tick at the clock's `now_ns`: a dispatcher pass if due, then housekeeping.
  void RunTick(int64_t now_ns);
  /// Marks robots stale and records pose history when they are due at `now_ns` (the clock's).
  void KeepHouse(int64_t now_ns);

  const Clock& clock() const { return *clock_; }
  FleetRegistry& registry() { return registry_; }
  MapCatalog& maps() { return *maps_; }
  SiteCatalog& site() { return *site_; }
  ZoneCatalog& zones() { return *zones_; }
  StopControl& stops() { return *stops_; }
  JobService& jobs() { return *jobs_; }
  TrafficPlanner& traffic_planner() { return *traffic_planner_; }
  OperatorTokenService& tokens() { return *tokens_; }
  RobotSessions& sessions() { return *sessions_; }
  /// Null unless the app authorizes callers.
  const std::shared_ptr<AccessControl>& access() const { return access_; }
  storage::PoseHistoryRepository& pose_history() { return *pose_history_repository_; }
  /// Grows with every job or job event stored: a reader that saw the same count has seen every
  /// job as it is.
  uint64_t job_changes() const { return job_changes_.load(std::memory_order_acquire); }
  /// Grows with every stop made or cleared.
  uint64_t stop_changes() const { return stop_changes_.load(std::memory_order_acquire); }
  /// Jobs by state, from the store.
  absl::StatusOr<std::map<JobState, int64_t>> CountJobsByState();
  /// The store's engine and place, never a password; after Open.
  std::string store_description() const { return db_ != nullptr ? db_->Describe() : ""; }
  /// The dispatcher's passes that assigned jobs, those that assigned exactly one (the
  /// replanning latency when a job is added), and the latter in the dispatcher's CPU time;
  /// read after Stop.
  PassFigures assigning_passes() const;
  PassFigures one_job_passes() const;
  PassFigures one_job_pass_cpu() const;
  /// Traffic coordination's searches (route predictions, ways round) in the CPU time of the
  /// thread they run on; read after Stop.
  PassFigures traffic_search_cpu() const;

 private:
  FleetAppParams params_;
  const Clock* clock_;
  RobotMailbox* robots_;
  std::atomic<uint64_t> job_changes_{0};
  std::atomic<uint64_t> stop_changes_{0};
  std::atomic<bool> lockstep_{false};  ///< EnterLockstep was called
  FleetRegistry registry_;
  std::unique_ptr<storage::SqlDatabase> db_;
  std::unique_ptr<storage::SqlMapRepository> map_repository_;
  std::unique_ptr<storage::SqlMarkerSetRepository> marker_repository_;
  std::unique_ptr<storage::SqlRouteRepository> route_repository_;
  std::unique_ptr<storage::SqlZoneSetRepository> zone_repository_;
  std::unique_ptr<storage::SqlStopRepository> stop_repository_;
  std::unique_ptr<storage::SqlRobotRepository> robot_repository_;
  std::unique_ptr<storage::SqlJobRepository> stored_jobs_;
  std::unique_ptr<NotifyingJobRepository> job_repository_;
  std::unique_ptr<storage::SqlPoseHistoryRepository> pose_history_repository_;
  std::unique_ptr<storage::SqlOperatorTokenRepository> token_repository_;
  std::shared_ptr<AccessControl> access_;  ///< null unless authorizing
  std::unique_ptr<OperatorTokenService> tokens_;
  std::unique_ptr<PoseHistoryRecorder> pose_recorder_;
  std::unique_ptr<SiteCache> site_data_;  ///< in front of the site repositories
  std::unique_ptr<MapCatalog> maps_;
  std::unique_ptr<SiteCatalog> site_;
  std::unique_ptr<ZoneCatalog> zones_;
  std::unique_ptr<StopControl> stops_;
  std::unique_ptr<TrafficCoordinator> coordinator_;
  std::unique_ptr<JobService> jobs_;
  std::unique_ptr<RobotSessions> sessions_;
  std::unique_ptr<TrafficPlanner> traffic_planner_;
  std::unique_ptr<DispatcherLoop> dispatcher_;
  /// Stale robots, pose history and returning freed memory, off the dispatcher's thread.
  std::thread housekeeper_;
  absl::Notification stop_housekeeping_;
  absl::Mutex house_mutex_;
  std::optional<int64_t> next_stale_ns_ ABSL_GUARDED_BY(house_mutex_);
  std::optional<int64_t> next_history_ns_ ABSL_GUARDED_BY(house_mutex_);
};

}  // namespace fleetnav::server
