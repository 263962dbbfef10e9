#include "fleetnav/server/rpc/fleet_server.hpp"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/security/server_credentials.h>
#include <grpcpp/server_builder.h>
#include <malloc.h>

#include <algorithm>
#include <chrono>

#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/server/rpc/health_service.hpp"
#include "fleetnav/server/rpc/replica_relay.hpp"
#include "fleetnav/storage/fleet_database.hpp"

namespace fleetnav::server {

absl::Status FleetServerParams::Validate() const {
  if (listen_address.empty()) return absl::InvalidArgumentError("listen_address: empty");
  RETURN_IF_ERROR(limits.Validate());
  if (db_path.empty()) return absl::InvalidArgumentError("db_path: empty");
  if (!(postgres.connect_wait_s >= 0.0 && postgres.connect_wait_s <= 3600.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("db_wait_s: must be in [0, 3600], got ", postgres.connect_wait_s));
  }
  if (max_message_bytes < 1024) {
    return absl::InvalidArgumentError(
        absl::StrCat("max_message_bytes: must be >= 1024, got ", max_message_bytes));
  }
  if (!(dispatch_period_s > 0.0 && dispatch_period_s <= 10.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("dispatch_period_s: must be in (0, 10], got ", dispatch_period_s));
  }
  if (agent_stream_threads < 1 || agent_stream_threads > 64) {
    return absl::InvalidArgumentError(
        absl::StrCat("agent_stream_threads: must be in [1, 64], got ", agent_stream_threads));
  }
  RETURN_IF_ERROR(jobs.Validate());
  RETURN_IF_ERROR(traffic.Validate());
  RETURN_IF_ERROR(pose_history.Validate());
  return registry.Validate();
}

FleetServer::FleetServer(FleetServerParams params)
    : params_(std::move(params)),
      // On the simulator's clock, records are stamped with the simulation's calendar start (read
      // from the simulator at Start) plus simulated time; the server's own start until then.
      sim_clock_(0, SystemClock().UnixMs()),
      clock_(params_.sim_clock_address.empty() ? static_cast<const Clock*>(&system_clock_)
                                               : &sim_clock_),
      registry_(clock_, params_.registry) {}

FleetServer::~FleetServer() { Shutdown(); }

absl::StatusOr<int> FleetServer::Start() {
  RETURN_IF_ERROR(params_.Validate());
  // Credentials first: a bad certificate or token file must not leave a database behind.
  std::shared_ptr<grpc::ServerCredentials> credentials = grpc::InsecureServerCredentials();
  std::vector<OperatorToken> file_tokens;
  if (!params_.security.empty()) {
    ASSIGN_OR_RETURN(const ServerSecurity security, LoadServerSecurity(params_.security));
    file_tokens = security.tokens;
    // The file's tokens until the stored ones are read (before the port opens).
    ASSIGN_OR_RETURN(AccessPolicy policy, AccessPolicy::Create(security.tokens));
    std::string relay_key;
    if (params_.accept_replica_relays) {
      ASSIGN_OR_RETURN(relay_key, ReplicaRelayKey(security.private_key_pem));
    }
    access_gate_ =
        std::make_shared<AccessGate>(std::make_shared<const AccessPolicy>(std::move(policy)),
                                     params_.on_access_refused, std::move(relay_key));
    // Robots present certificates of the robot CA; operators present tokens over TLS without
    // one. A certificate that is presented must verify.
    grpc::SslServerCredentialsOptions options(GRPC_SSL_REQUEST_CLIENT_CERTIFICATE_AND_VERIFY);
    options.pem_root_certs = security.client_ca_pem;
    options.pem_key_cert_pairs.push_back({security.private_key_pem, security.cert_chain_pem});
    credentials = grpc::SslServerCredentials(options);
    credentials->SetAuthMetadataProcessor(access_gate_);
  }
  if (!params_.sim_clock_address.empty()) {
    sim_clock_feed_ = std::make_unique<SimClockFeed>(params_.sim_clock_address, &sim_clock_);
    RETURN_IF_ERROR(sim_clock_feed_->Start());
  }
  ASSIGN_OR_RETURN(db_, storage::OpenFleetDatabase(params_.db_path, params_.postgres));
  db_->SetTransactionObserver(
      [this](double seconds) { metrics_.ObserveStoreTransaction(seconds); });
  map_repository_ = std::make_unique<storage::SqlMapRepository>(db_.get());
  marker_repository_ = std::make_unique<storage::SqlMarkerSetRepository>(db_.get());
  route_repository_ = std::make_unique<storage::SqlRouteRepository>(db_.get());
  robot_repository_ = std::make_unique<storage::SqlRobotRepository>(db_.get());
  stored_jobs_ = std::make_unique<storage::SqlJobRepository>(db_.get());
  job_repository_ =
      std::make_unique<NotifyingJobRepository>(stored_jobs_.get(), params_.on_job_event);
  pose_history_repository_ = std::make_unique<storage::SqlPoseHistoryRepository>(db_.get());
  token_repository_ = std::make_unique<storage::SqlOperatorTokenRepository>(db_.get());
  // Without TLS nothing checks tokens; they are still kept for when the server gets TLS.
  tokens_ = std::make_unique<OperatorTokenService>(
      token_repository_.get(), std::move(file_tokens), clock_,
      [gate = access_gate_](std::shared_ptr<const AccessPolicy> policy) {
        if (gate != nullptr) gate->ReplacePolicy(std::move(policy));
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
  coordinator_ = std::make_unique<TrafficCoordinator>(site_data_.get(), &registry_, &mailbox_,
                                                      clock_, params_.traffic);
  jobs_ = std::make_unique<JobService>(job_repository_.get(), robot_repository_.get(),
                                       site_data_.get(), site_.get(), &registry_, &mailbox_, clock_,
                                       params_.jobs, coordinator_.get());
  RETURN_IF_ERROR(jobs_->Recover());
  traffic_ = std::make_unique<TrafficPlanner>(site_data_.get());
  fleet_service_ = std::make_unique<FleetServiceImpl>(maps_.get(), site_.get(), jobs_.get(),
                                                      traffic_.get(), &registry_, &mailbox_);
  access_service_ = std::make_unique<AccessServiceImpl>(tokens_.get(), params_.on_token_change);
  dispatcher_ = std::make_unique<DispatcherLoop>(
      jobs_.get(), params_.dispatch_period_s,
      [this](double seconds) { metrics_.ObserveDispatchPass(seconds); });
  TickWork tick_work;
  tick_work.first_join = [this] {
    // The simulator is held while agents join (fleetnav-scenario): the clock read last is the
    // tick's. From now on only the ticks move it.
    if (sim_clock_feed_ != nullptr) sim_clock_feed_->Stop();
    dispatcher_->TakeOver();
  };
  tick_work.begin = [this](int64_t sim_time_ns) {
    if (clock_ == &sim_clock_) sim_clock_.SetNs(sim_time_ns);
  };
  tick_work.end = [this] {
    dispatcher_->RunPassIfDue(clock_->NowNs());
    KeepHouse(clock_->NowNs());
  };
  barrier_ = std::make_unique<TickBarrier>(std::move(tick_work));
  agent_service_ = std::make_unique<AgentServiceImpl>(&registry_, jobs_.get(), &mailbox_,
                                                      params_.agent_stream_threads, params_.limits,
                                                      access_gate_.get(), barrier_.get());
  watch_hub_ = std::make_unique<WatchHub>(fleet_service_.get(), &registry_, jobs_.get());
  registry_.SetChangeListener([hub = watch_hub_.get()] { hub->OnFleetChanged(); });
  job_repository_->SetListener([this, hub = watch_hub_.get()](const std::string& job_id) {
    job_changes_.fetch_add(1, std::memory_order_release);
    hub->OnJobChanged(job_id);
  });

  // Our own synchronous health service instead of gRPC's default (see health_service.hpp); the
  // default is switched on process-wide, so switch it off for this server explicitly.
  grpc::EnableDefaultHealthCheckService(false);
  health_service_ = std::make_unique<HealthServiceImpl>(
      std::vector<std::string>{v1::FleetService::service_full_name(),
                               v1::AgentService::service_full_name(),
                               v1::AccessService::service_full_name()},
      &stopping_);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  int port = 0;
  if (access_gate_ != nullptr) {
    // A TLS port is accepted by fleetnavd itself, so that refused handshakes name their peer.
    front_door_ = std::make_unique<TlsFrontDoor>(
        TlsFrontDoorParams{params_.listen_address, params_.on_access_refused});
    absl::StatusOr<int> opened = front_door_->Open(&builder, credentials);
    if (!opened.ok()) return opened.status();
    port = *opened;
  } else {
    builder.AddListeningPort(params_.listen_address, credentials, &port);
  }
  // gRPC binds with SO_REUSEPORT by default: a second server on a bound port would start and
  // the kernel would split the clients between the two. The port must be this server's alone.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.SetMaxReceiveMessageSize(params_.max_message_bytes);
  builder.SetMaxSendMessageSize(params_.max_message_bytes);
  std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> counting;
  counting.push_back(metrics_.InterceptorFactory());
  builder.experimental().SetInterceptorCreators(std::move(counting));
  builder.RegisterService(health_service_.get());
  builder.RegisterService(fleet_service_.get());
  builder.RegisterService(access_service_.get());
  agent_service_->Register(&builder);
  watch_hub_->Register(&builder);
  server_ = builder.BuildAndStart();
  if (server_ == nullptr || port == 0) {
    return absl::UnavailableError(absl::StrCat("cannot listen: address ", params_.listen_address,
                                               " already in use or not available"));
  }
  if (front_door_ != nullptr) front_door_->Start();
  agent_service_->Start();
  watch_hub_->Start();
  dispatcher_->Start();
  housekeeper_ = std::thread([this] {
    // Wakes often and compares the server's clock (the simulator's with --clock sim) with what
    // is due; the wall clock only paces the wake-ups and the memory trim.
    const absl::Duration wake_period = absl::Milliseconds(50);
    const absl::Duration trim_period = absl::Seconds(5);
    absl::Time next_trim = absl::Now() + trim_period;
    while (!stop_housekeeping_.WaitForNotificationWithTimeout(wake_period)) {
      // In lockstep the ticks keep house, at the ticks' times.
      if (!barrier_->active()) KeepHouse(clock_->NowNs());
      if (absl::Now() >= next_trim) {
        // Large requests (a 100,000-marker set, a 10,000-action route, their assignments) are
        // parsed and sent through many small allocations; glibc keeps the freed pages mapped
        // between live ones, so the server's memory would stay at its peak for good.
        malloc_trim(0);
        next_trim = absl::Now() + trim_period;
      }
    }
  });
  return port;
}

void FleetServer::KeepHouse(int64_t now_ns) {
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

PassFigures FleetServer::assigning_passes() const {
  return dispatcher_ ? dispatcher_->assigning_passes() : PassFigures{};
}

std::string FleetServer::RenderMetrics() const {
  FleetStateFigures state;
  for (const RobotRecord& robot : registry_.Snapshot()) {
    ++state.robots_by_state[std::string(ConnectionStateName(robot.connection))];
  }
  if (job_repository_ != nullptr) {
    if (absl::StatusOr<std::map<JobState, int64_t>> jobs = job_repository_->CountJobsByState();
        jobs.ok()) {
      for (const auto& [job_state, count] : *jobs) {
        state.jobs_by_state[std::string(JobStateName(job_state))] = count;
      }
    }
  }
  state.telemetry_messages = agent_service_ ? agent_service_->telemetry_messages() : 0;
  state.access = access_counts();
  return metrics_.Render(state);
}

AccessCounts FleetServer::access_counts() const {
  AccessCounts counts = access_gate_ ? access_gate_->counts() : AccessCounts{};
  if (front_door_ != nullptr) counts.handshakes_refused = front_door_->refused();
  return counts;
}

PassFigures FleetServer::one_job_passes() const {
  return dispatcher_ ? dispatcher_->one_job_passes() : PassFigures{};
}

PassFigures FleetServer::one_job_pass_cpu() const {
  return dispatcher_ ? dispatcher_->one_job_pass_cpu() : PassFigures{};
}

void FleetServer::Shutdown() {
  if (server_ == nullptr || stopping_.exchange(true)) return;
  if (front_door_ != nullptr) front_door_->Stop();
  server_->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(1));
  agent_service_->Shutdown();
  watch_hub_->Shutdown();
  registry_.SetChangeListener(nullptr);
  if (dispatcher_ != nullptr) dispatcher_->Stop();
  stop_housekeeping_.Notify();
  if (housekeeper_.joinable()) housekeeper_.join();
  if (sim_clock_feed_ != nullptr) sim_clock_feed_->Stop();
}

std::shared_ptr<grpc::Channel> FleetServer::InProcessChannel(int max_message_bytes) {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(max_message_bytes);
  arguments.SetMaxSendMessageSize(max_message_bytes);
  return server_->InProcessChannel(arguments);
}

void FleetServer::Wait() {
  if (server_ != nullptr) server_->Wait();
}

}  // namespace fleetnav::server
