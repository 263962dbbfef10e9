#include "fleetnav/server/fleet_app.hpp"

#include <malloc.h>

#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/fleet_database.hpp"

namespace fleetnav::server {

absl::Status FleetAppParams::Validate() const {
  RETURN_IF_ERROR(limits.Validate());
  if (db_path.empty()) return absl::InvalidArgumentError("db_path: empty");
  if (!(postgres.connect_wait_s >= 0.0 && postgres.connect_wait_s <= 3600.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("db_wait_s: must be in [0, 3600], got ", postgres.connect_wait_s));
  }
  if (!(dispatch_period_s > 0.0 && dispatch_period_s <= 10.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("dispatch_period_s: must be in (0, 10], got ", dispatch_period_s));
  }
  RETURN_IF_ERROR(jobs.Validate());
  RETURN_IF_ERROR(traffic.Validate());
  RETURN_IF_ERROR(pose_history.Validate());
  return registry.Validate();
}

FleetApp::FleetApp(FleetAppParams params, const Clock* clock, RobotMailbox* robots)
    : params_(std::move(params)),
      clock_(clock),
      robots_(robots),
      registry_(clock_, params_.registry) {}

FleetApp::~FleetApp() { Stop(); }

absl::Status FleetApp::Open() {
  RETURN_IF_ERROR(params_.Validate());
  if (params_.authorize) {
    // The file's tokens until the stored ones are read (before any call is taken).
    ASSIGN_OR_RETURN(AccessPolicy policy, AccessPolicy::Create(params_.file_tokens));
    access_ = std::make_shared<AccessControl>(
        std::make_shared<const AccessPolicy>(std::move(policy)), params_.on_access_refused);
  }
  ASSIGN_OR_RETURN(db_, storage::OpenFleetDatabase(params_.db_path, params_.postgres));
  if (params_.on_store_transaction) db_->SetTransactionObserver(params_.on_store_transaction);
  map_repository_ = std::make_unique<storage::SqlMapRepository>(db_.get());
  marker_repository_ = std::make_unique<storage::SqlMarkerSetRepository>(db_.get());
  route_repository_ = std::make_unique<storage::SqlRouteRepository>(db_.get());
  zone_repository_ = std::make_unique<storage::SqlZoneSetRepository>(db_.get());
  stop_repository_ = std::make_unique<storage::SqlStopRepository>(db_.get());
  robot_repository_ = std::make_unique<storage::SqlRobotRepository>(db_.get());
  stored_jobs_ = std::make_unique<storage::SqlJobRepository>(db_.get());
  job_repository_ =
      std::make_unique<NotifyingJobRepository>(stored_jobs_.get(), params_.on_job_event);
  job_repository_->SetListener([this](const std::string& job_id) {
    job_changes_.fetch_add(1, std::memory_order_release);
    if (params_.on_job_changed) params_.on_job_changed(job_id);
  });
  pose_history_repository_ = std::make_unique<storage::SqlPoseHistoryRepository>(db_.get());
  token_repository_ = std::make_unique<storage::SqlOperatorTokenRepository>(db_.get());
  // Without authorization nothing checks tokens; they are still kept for when it is switched on.
  tokens_ = std::make_unique<OperatorTokenService>(
      token_repository_.get(), params_.file_tokens, clock_,
      [access = access_](std::shared_ptr<const AccessPolicy> policy) {
        if (access != nullptr) access->ReplacePolicy(std::move(policy));
      });
  ASSIGN_OR_RETURN(const std::vector<std::string> token_conflicts, tokens_->Load());
  for (const std::string& conflict : token_conflicts) {
    if (params_.on_token_change) params_.on_token_change(conflict);
  }
  pose_recorder_ = std::make_unique<PoseHistoryRecorder>(&registry_, pose_history_repository_.get(),
                                                         params_.pose_history);
  site_data_ = std::make_unique<SiteCache>(map_repository_.get(), marker_repository_.get(),
                                           route_repository_.get(), params_.site_cache);
  maps_ = std::make_unique<MapCatalog>(site_data_.get(), clock_, params_.limits);
  site_ = std::make_unique<SiteCatalog>(site_data_.get(), job_repository_.get(), clock_,
                                        params_.limits);
  zones_ = std::make_unique<ZoneCatalog>(zone_repository_.get(), site_data_.get(), clock_,
                                         params_.limits);
  site_->UseZones(zones_.get());
  // Every robot hears each new zone version at once: those driving on the map keep to it.
  zones_->SetChangeListener([this](const std::string& map_id) {
    const std::shared_ptr<const storage::StoredZoneSet> latest = zones_->Latest(map_id);
    ZoneSet none;
    none.map_id = map_id;
    robots_->BroadcastZones(latest != nullptr ? latest->version : 0,
                            latest != nullptr ? latest->zones : none);
    if (coordinator_ != nullptr) coordinator_->ZonesChanged();
  });
  coordinator_ = std::make_unique<TrafficCoordinator>(site_data_.get(), &registry_, robots_, clock_,
                                                      params_.traffic);
  coordinator_->UseZones(zones_.get());
  stops_ = std::make_unique<StopControl>(stop_repository_.get(), zones_.get(), clock_);
  // Every robot hears each change of the stops; traffic plans ways round stopped zones.
  stops_->SetChangeListener([this](const std::vector<RobotStop>& stops) {
    stop_changes_.fetch_add(1, std::memory_order_release);
    robots_->BroadcastStops(stops);
    coordinator_->SetStops(stops);
  });
  ASSIGN_OR_RETURN(std::vector<RobotStop> stops_in_force, stops_->InForce());
  coordinator_->SetStops(std::move(stops_in_force));
  jobs_ = std::make_unique<JobService>(job_repository_.get(), robot_repository_.get(),
                                       site_data_.get(), site_.get(), &registry_, robots_, clock_,
                                       params_.jobs, coordinator_.get());
  RETURN_IF_ERROR(jobs_->Recover());
  sessions_ = std::make_unique<RobotSessions>(&registry_, jobs_.get(), robots_, maps_.get(),
                                              site_.get(), params_.limits);
  sessions_->UseStops(stops_.get());
  // Robots hear of every new map or marker-set version.
  maps_->SetChangeListener([this](const std::string& map_id) { sessions_->AnnounceSite(map_id); });
  site_->SetMarkerChangeListener(
      [this](const std::string& map_id) { sessions_->AnnounceSite(map_id); });
  traffic_planner_ = std::make_unique<TrafficPlanner>(site_data_.get());
  traffic_planner_->UseZones(zones_.get());
  dispatcher_ = std::make_unique<DispatcherLoop>(jobs_.get(), params_.dispatch_period_s,
                                                 params_.on_dispatch_pass);
  dispatcher_->SetTraffic(coordinator_.get());
  return absl::OkStatus();
}

void FleetApp::Start(std::function<bool()> ticks_keep_house) {
  // A finished search wakes the dispatcher to take it up; in lockstep the ticks run the passes
  // instead (a wake at a moment of the wall clock would make runs differ).
  coordinator_->StartSearchThread([this] {
    if (!lockstep_.load()) jobs_->WakeDispatcher();
  });
  dispatcher_->Start();
  housekeeper_ = std::thread([this, ticks_keep_house = std::move(ticks_keep_house)] {
    // Wakes often and compares the app's clock (the simulator's with --clock sim) with what is
    // due; the wall clock only paces the wake-ups and the memory trim.
    const absl::Duration wake_period = absl::Milliseconds(50);
    const absl::Duration trim_period = absl::Seconds(5);
    absl::Time next_trim = absl::Now() + trim_period;
    while (!stop_housekeeping_.WaitForNotificationWithTimeout(wake_period)) {
      if (!ticks_keep_house || !ticks_keep_house()) KeepHouse(clock_->NowNs());
      if (absl::Now() >= next_trim) {
        // Large requests (a 100,000-marker set, a 10,000-action route, their assignments) are
        // parsed and sent through many small allocations; glibc keeps the freed pages mapped
        // between live ones, so the server's memory would stay at its peak for good.
        malloc_trim(0);
        next_trim = absl::Now() + trim_period;
      }
    }
  });
}

void FleetApp::Stop() {
  if (dispatcher_ != nullptr) dispatcher_->Stop();
  if (coordinator_ != nullptr) coordinator_->StopSearchThread();
  if (!stop_housekeeping_.HasBeenNotified()) stop_housekeeping_.Notify();
  if (housekeeper_.joinable()) housekeeper_.join();
}

void FleetApp::EnterLockstep() {
  lockstep_.store(true);
  dispatcher_->TakeOver();
}

void FleetApp::RunTick(int64_t now_ns) {
  dispatcher_->RunPassIfDue(now_ns);
  KeepHouse(now_ns);
}

void FleetApp::KeepHouse(int64_t now_ns) {
  absl::MutexLock lock(&house_mutex_);
  const auto history_period_ns = static_cast<int64_t>(params_.pose_history.period_s * 1e9);
  const auto stale_period_ns = static_cast<int64_t>(params_.dispatch_period_s * 1e9);
  // Once a period: it walks every robot under the registry's lock.
  if (!next_stale_ns_ || now_ns >= *next_stale_ns_) {
    registry_.RefreshStale();
    next_stale_ns_ = now_ns + stale_period_ns;
  }
  if (!next_history_ns_) {
    next_history_ns_ = now_ns + history_period_ns;
  } else if (now_ns >= *next_history_ns_) {
    (void)pose_recorder_->RecordOnce(clock_->UnixMs());
    // On schedule, unless the clock jumped (a simulator that ran on while the server was away).
    *next_history_ns_ += history_period_ns;
    if (*next_history_ns_ <= now_ns) next_history_ns_ = now_ns + history_period_ns;
  }
}

absl::StatusOr<std::map<JobState, int64_t>> FleetApp::CountJobsByState() {
  if (job_repository_ == nullptr) return std::map<JobState, int64_t>{};
  return job_repository_->CountJobsByState();
}

PassFigures FleetApp::assigning_passes() const {
  return dispatcher_ ? dispatcher_->assigning_passes() : PassFigures{};
}

PassFigures FleetApp::one_job_passes() const {
  return dispatcher_ ? dispatcher_->one_job_passes() : PassFigures{};
}

PassFigures FleetApp::one_job_pass_cpu() const {
  return dispatcher_ ? dispatcher_->one_job_pass_cpu() : PassFigures{};
}

PassFigures FleetApp::traffic_search_cpu() const {
  return coordinator_ ? coordinator_->search_cpu() : PassFigures{};
}

}  // namespace fleetnav::server
