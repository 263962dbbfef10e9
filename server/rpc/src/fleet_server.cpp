#include "fleetnav/server/rpc/fleet_server.hpp"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/security/server_credentials.h>
#include <grpcpp/server_builder.h>

#include <algorithm>
#include <chrono>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/server/rpc/health_service.hpp"
#include "fleetnav/server/rpc/replica_relay.hpp"

namespace fleetnav::server {

absl::Status FleetServerParams::Validate() const {
  if (listen_address.empty()) return absl::InvalidArgumentError("listen_address: empty");
  if (max_message_bytes < 1024) {
    return absl::InvalidArgumentError(
        absl::StrCat("max_message_bytes: must be >= 1024, got ", max_message_bytes));
  }
  if (agent_stream_threads < 1 || agent_stream_threads > 64) {
    return absl::InvalidArgumentError(
        absl::StrCat("agent_stream_threads: must be in [1, 64], got ", agent_stream_threads));
  }
  return FleetAppParams::Validate();
}

FleetServer::FleetServer(FleetServerParams params)
    : params_(std::move(params)),
      // On the simulator's clock, records are stamped with the simulation's calendar start (read
      // from the simulator at Start) plus simulated time; the server's own start until then.
      sim_clock_(0, SystemClock().UnixMs()),
      clock_(params_.sim_clock_address.empty() ? static_cast<const Clock*>(&system_clock_)
                                               : &sim_clock_) {}

FleetServer::~FleetServer() { Shutdown(); }

absl::StatusOr<int> FleetServer::Start() {
  RETURN_IF_ERROR(params_.Validate());
  FleetAppParams app_params = params_;  // the app's part of the parameters
  app_params.authorize = false;         // the security files decide (below)
  app_params.file_tokens.clear();
  app_params.on_store_transaction = [this](double seconds) {
    metrics_.ObserveStoreTransaction(seconds);
  };
  app_params.on_dispatch_pass = [this](double seconds) { metrics_.ObserveDispatchPass(seconds); };
  app_params.on_job_changed = [this](const std::string& job_id) {
    if (watch_hub_ != nullptr) watch_hub_->OnJobChanged(job_id);
  };
  // Credentials first: a bad certificate or token file must not leave a database behind.
  std::shared_ptr<grpc::ServerCredentials> credentials = grpc::InsecureServerCredentials();
  std::optional<ServerSecurity> security;
  std::string relay_key;
  if (!params_.security.empty()) {
    ASSIGN_OR_RETURN(security, LoadServerSecurity(params_.security));
    app_params.authorize = true;
    app_params.file_tokens = security->tokens;
    if (params_.accept_replica_relays) {
      ASSIGN_OR_RETURN(relay_key, ReplicaRelayKey(security->private_key_pem));
    }
    // Robots present certificates of the robot CA; operators present tokens over TLS without
    // one. A certificate that is presented must verify.
    grpc::SslServerCredentialsOptions options(GRPC_SSL_REQUEST_CLIENT_CERTIFICATE_AND_VERIFY);
    options.pem_root_certs = security->client_ca_pem;
    options.pem_key_cert_pairs.push_back({security->private_key_pem, security->cert_chain_pem});
    credentials = grpc::SslServerCredentials(options);
  }
  if (!params_.sim_clock_address.empty()) {
    sim_clock_feed_ = std::make_unique<SimClockFeed>(params_.sim_clock_address, &sim_clock_);
    RETURN_IF_ERROR(sim_clock_feed_->Start());
  }
  app_ = std::make_unique<FleetApp>(std::move(app_params), clock_, &mailbox_);
  RETURN_IF_ERROR(app_->Open());
  if (app_->access() != nullptr) {
    access_gate_ = std::make_shared<AccessGate>(app_->access(), std::move(relay_key));
    credentials->SetAuthMetadataProcessor(access_gate_);
  }
  fleet_service_ = std::make_unique<FleetServiceImpl>(&app_->maps(), &app_->site(), &app_->zones(),
                                                      &app_->stops(), &app_->jobs(),
                                                      &app_->traffic_planner(), &app_->registry());
  access_service_ = std::make_unique<AccessServiceImpl>(&app_->tokens(), params_.on_token_change);
  TickWork tick_work;
  tick_work.first_join = [this] {
    // The simulator is held while agents join (fleetnav-scenario): the clock read last is the
    // tick's. From now on only the ticks move it.
    if (sim_clock_feed_ != nullptr) sim_clock_feed_->Stop();
    app_->EnterLockstep();
  };
  tick_work.begin = [this](int64_t sim_time_ns) {
    if (clock_ == &sim_clock_) sim_clock_.SetNs(sim_time_ns);
  };
  tick_work.end = [this] { app_->RunTick(clock_->NowNs()); };
  barrier_ = std::make_unique<TickBarrier>(std::move(tick_work));
  agent_service_ =
      std::make_unique<AgentServiceImpl>(&app_->sessions(), &mailbox_, params_.agent_stream_threads,
                                         access_gate_.get(), barrier_.get());
  watch_hub_ = std::make_unique<WatchHub>(fleet_service_.get(), &app_->registry(), &app_->jobs());
  app_->registry().SetChangeListener([hub = watch_hub_.get()] { hub->OnFleetChanged(); });

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
  app_->Start([barrier = barrier_.get()] { return barrier->active(); });
  return port;
}

PassFigures FleetServer::assigning_passes() const {
  return app_ ? app_->assigning_passes() : PassFigures{};
}

std::string FleetServer::RenderMetrics() const {
  FleetStateFigures state;
  if (app_ == nullptr) return metrics_.Render(state);
  for (const RobotRecord& robot : app_->registry().Snapshot()) {
    ++state.robots_by_state[std::string(ConnectionStateName(robot.connection))];
  }
  {
    if (absl::StatusOr<std::map<JobState, int64_t>> jobs = app_->CountJobsByState(); jobs.ok()) {
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
  AccessCounts counts =
      app_ != nullptr && app_->access() != nullptr ? app_->access()->counts() : AccessCounts{};
  if (front_door_ != nullptr) counts.handshakes_refused = front_door_->refused();
  return counts;
}

PassFigures FleetServer::one_job_passes() const {
  return app_ ? app_->one_job_passes() : PassFigures{};
}

PassFigures FleetServer::one_job_pass_cpu() const {
  return app_ ? app_->one_job_pass_cpu() : PassFigures{};
}

PassFigures FleetServer::traffic_search_cpu() const {
  return app_ ? app_->traffic_search_cpu() : PassFigures{};
}

void FleetServer::Shutdown() {
  if (server_ == nullptr || stopping_.exchange(true)) return;
  if (front_door_ != nullptr) front_door_->Stop();
  server_->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(1));
  agent_service_->Shutdown();
  watch_hub_->Shutdown();
  app_->registry().SetChangeListener(nullptr);
  app_->Stop();
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
