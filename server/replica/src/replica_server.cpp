#include "fleetnav/server/replica/replica_server.hpp"

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/security/server_credentials.h>
#include <grpcpp/server_builder.h>

#include <chrono>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/postgres/pg_schema.hpp"
#include "fleetnav/v1/access_service.grpc.pb.h"
#include "fleetnav/v1/agent_service.grpc.pb.h"
#include "fleetnav/v1/fleet_service.grpc.pb.h"

namespace fleetnav::server {
namespace {

/// The host part of host:port ("[::1]:5" → "[::1]").
std::string HostOf(const std::string& address) {
  const size_t colon = address.rfind(':');
  return colon == std::string::npos ? address : address.substr(0, colon);
}

bool IsWildcardHost(const std::string& host) {
  return host.empty() || host == "0.0.0.0" || host == "[::]" || host == "::";
}

}  // namespace

absl::Status ReplicaParams::Validate() const {
  if (!storage::IsPostgresUri(leader.db_path)) {
    return absl::InvalidArgumentError(
        absl::StrCat("replicas share a PostgreSQL database (--db postgresql://...); '",
                     leader.db_path, "' is an SQLite file, which serves one fleetnavd"));
  }
  if (!leader.security.empty()) {
    return absl::InvalidArgumentError(
        "replicas serve plaintext only for now (--insecure): relaying robot certificates "
        "between replicas is not built yet");
  }
  if (listen_address.empty()) return absl::InvalidArgumentError("listen_address: empty");
  if (advertise_address.empty() && IsWildcardHost(HostOf(leader.listen_address))) {
    return absl::InvalidArgumentError(
        absl::StrCat("the leader port listens on '", leader.listen_address,
                     "': give the address the other replicas reach it at (--peer-advertise)"));
  }
  RETURN_IF_ERROR(leadership.Validate());
  return leader.Validate();
}

ReplicaServer::ReplicaServer(ReplicaParams params) : params_(std::move(params)) {}

ReplicaServer::~ReplicaServer() { Shutdown(); }

absl::StatusOr<int> ReplicaServer::Start() {
  RETURN_IF_ERROR(params_.Validate());
  storage::PgOpenOptions lease_options = params_.leader.postgres;
  lease_options.connections = 2;
  // A database of a newer schema is refused here, naming both versions, before this replica
  // serves anything.
  ASSIGN_OR_RETURN(lease_db_, storage::PgDatabase::Open(params_.leader.db_path,
                                                        storage::PostgresFleetSchemaMigrations(),
                                                        lease_options));
  leases_ =
      std::make_unique<storage::PgSiteLeases>(lease_db_.get(), params_.leadership.lease_ttl_s);
  leadership_ = std::make_unique<SiteLeadership>(
      leases_.get(), &clock_, NewLeaseHolderId(), params_.leadership,
      SiteLeadershipEvents{[this](int64_t epoch) { OnElected(epoch); },
                           [this](const storage::SiteLease& lease) { OnLeaderChanged(lease); },
                           [this](const std::string& why) {
                             leading_epoch_ = 0;
                             if (params_.on_leadership_lost) params_.on_leadership_lost(why);
                           }});

  health_ = std::make_unique<HealthServiceImpl>(
      std::vector<std::string>{v1::FleetService::service_full_name(),
                               v1::AgentService::service_full_name(),
                               v1::AccessService::service_full_name()},
      &stopping_);
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(params_.listen_address, grpc::InsecureServerCredentials(), &port);
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.SetMaxReceiveMessageSize(params_.leader.max_message_bytes);
  builder.SetMaxSendMessageSize(params_.leader.max_message_bytes);
  builder.RegisterService(health_.get());
  builder.RegisterCallbackGenericService(&proxy_);
  server_ = builder.BuildAndStart();
  if (server_ == nullptr || port == 0) {
    return absl::UnavailableError(absl::StrCat("cannot listen: address ", params_.listen_address,
                                               " already in use or not available"));
  }
  leadership_->Start();
  return port;
}

void ReplicaServer::OnElected(int64_t epoch) {
  leading_epoch_ = epoch;
  Tell(absl::StrCat("site '", params_.leadership.site, "': this replica (", holder(),
                    ") won the lease at epoch ", epoch, "; starting to lead"));
  starter_ = std::thread([this, epoch] { Lead(epoch); });
}

void ReplicaServer::Lead(int64_t epoch) {
  FleetServerParams leader_params = params_.leader;
  leader_params.postgres.fence = storage::PgFence{params_.leadership.site, epoch};
  auto leader = std::make_unique<FleetServer>(leader_params);
  absl::StatusOr<int> port = leader->Start();
  if (!port.ok()) {
    if (params_.on_leadership_lost) {
      params_.on_leadership_lost(absl::StrCat(
          "cannot start leading site '", params_.leadership.site, "': ", port.status().ToString()));
    }
    return;
  }
  const std::string address = params_.advertise_address.empty()
                                  ? absl::StrCat(HostOf(params_.leader.listen_address), ":", *port)
                                  : params_.advertise_address;
  proxy_.SetLeader(epoch, leader->InProcessChannel(params_.leader.max_message_bytes));
  {
    absl::MutexLock lock(&leader_mutex_);
    leader_ = std::move(leader);
  }
  if (absl::Status published = leadership_->Publish(epoch, address); !published.ok()) {
    if (params_.on_leadership_lost) params_.on_leadership_lost(std::string(published.message()));
    return;
  }
  Tell(absl::StrCat("site '", params_.leadership.site, "': leading at epoch ", epoch,
                    " (jobs recovered, dispatching); the other replicas relay to ", address));
}

void ReplicaServer::OnLeaderChanged(const storage::SiteLease& lease) {
  if (lease.holder == holder()) return;
  if (lease.address.empty()) {
    proxy_.SetLeader(lease.epoch, nullptr);
    Tell(absl::StrCat("site '", params_.leadership.site, "': replica ", lease.holder,
                      " leads at epoch ", lease.epoch, " and is starting"));
    return;
  }
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(params_.leader.max_message_bytes);
  arguments.SetMaxSendMessageSize(params_.leader.max_message_bytes);
  arguments.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, 100);
  arguments.SetInt(GRPC_ARG_MIN_RECONNECT_BACKOFF_MS, 100);
  arguments.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, 500);
  proxy_.SetLeader(lease.epoch, grpc::CreateCustomChannel(
                                    lease.address, grpc::InsecureChannelCredentials(), arguments));
  Tell(absl::StrCat("site '", params_.leadership.site, "': the leader is ", lease.holder, " at ",
                    lease.address, " (epoch ", lease.epoch, ")"));
}

void ReplicaServer::Shutdown() {
  if (server_ == nullptr || stopping_.exchange(true)) return;
  leadership_->Stop();
  proxy_.Close();
  server_->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(1));
  if (starter_.joinable()) starter_.join();
  std::unique_ptr<FleetServer> leader;
  {
    absl::MutexLock lock(&leader_mutex_);
    leader = std::move(leader_);
  }
  if (leader != nullptr) {
    leader->Shutdown();
    // Handing over: the next replica need not wait for the lease to run out.
    (void)leases_->Release(params_.leadership.site, holder(), leading_epoch_.load());
  }
}

}  // namespace fleetnav::server
