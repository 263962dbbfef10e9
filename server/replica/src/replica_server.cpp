#include "fleetnav/server/replica/replica_server.hpp"

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/security/server_credentials.h>
#include <grpcpp/server_builder.h>

#include <chrono>
#include <utility>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/server/rpc/replica_relay.hpp"
#include "fleetnav/server/rpc/server_security.hpp"
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

/// The lease's address: the leader port, then the leader's dashboard when it serves one.
constexpr char kDashboardMark[] = " http=";

std::string LeaseAddress(const std::string& leader_port, const std::string& dashboard) {
  return dashboard.empty() ? leader_port : absl::StrCat(leader_port, kDashboardMark, dashboard);
}

/// The leader port and the dashboard ("" when none) of a lease's address.
std::pair<std::string, std::string> SplitLeaseAddress(const std::string& address) {
  const size_t mark = address.find(kDashboardMark);
  if (mark == std::string::npos) return {address, ""};
  return {address.substr(0, mark), address.substr(mark + sizeof(kDashboardMark) - 1)};
}

}  // namespace

absl::Status ReplicaParams::Validate() const {
  if (!storage::IsPostgresUri(leader.db_path)) {
    return absl::InvalidArgumentError(
        absl::StrCat("replicas share a PostgreSQL database (--db postgresql://...); '",
                     leader.db_path, "' is an SQLite file, which serves one fleetnavd"));
  }
  if (listen_address.empty()) return absl::InvalidArgumentError("listen_address: empty");
  if (!leader_http_listen_address.empty() && http_listen_address.empty()) {
    return absl::InvalidArgumentError(
        "the leader's dashboard port (--peer-http-listen) needs the dashboard (--http-listen)");
  }
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
  // Credentials first: a bad certificate or token file must not touch the database.
  std::shared_ptr<grpc::ServerCredentials> credentials = grpc::InsecureServerCredentials();
  secure_ = !params_.leader.security.empty();
  if (secure_) {
    ASSIGN_OR_RETURN(const ServerSecurity security, LoadServerSecurity(params_.leader.security));
    ASSIGN_OR_RETURN(std::string relay_key, ReplicaRelayKey(security.private_key_pem));
    ASSIGN_OR_RETURN(leader_certificate_pem_, LeafCertificatePem(security.cert_chain_pem));
    // As the single server's port: robots present certificates of the robot CA, operators
    // tokens (checked by the leader); a certificate that is presented must verify.
    grpc::SslServerCredentialsOptions options(GRPC_SSL_REQUEST_CLIENT_CERTIFICATE_AND_VERIFY);
    options.pem_root_certs = security.client_ca_pem;
    options.pem_key_cert_pairs.push_back({security.private_key_pem, security.cert_chain_pem});
    credentials = grpc::SslServerCredentials(options);
    proxy_.SetRelayKey(std::move(relay_key));
    params_.leader.accept_replica_relays = true;
  }
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
  if (!params_.http_listen_address.empty()) {
    http::HttpRelayParams relay;
    relay.listen_address = params_.http_listen_address;
    relay.cert_path = params_.leader.security.cert_path;
    relay.key_path = params_.leader.security.key_path;
    relay.upstream_ca_path = params_.leader.security.cert_path;
    http_relay_ = std::make_unique<http::HttpRelay>([this] { return LeaderDashboard(); }, relay);
    ASSIGN_OR_RETURN(http_port_, http_relay_->Start());
  }
  grpc::ServerBuilder builder;
  int port = 0;
  if (secure_) {
    // As the single server's: refused handshakes are logged and counted with their peer.
    front_door_ = std::make_unique<TlsFrontDoor>(
        TlsFrontDoorParams{params_.listen_address, params_.leader.on_access_refused});
    ASSIGN_OR_RETURN(port, front_door_->Open(&builder, credentials));
  } else {
    builder.AddListeningPort(params_.listen_address, credentials, &port);
  }
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
  if (front_door_ != nullptr) front_door_->Start();
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
  // The dashboard the replicas' HTTP ports relay to, over this FleetServer.
  std::unique_ptr<http::HttpGateway> dashboard;
  std::string dashboard_address;
  if (!params_.http_listen_address.empty()) {
    http::HttpGatewayParams http_params;
    http_params.listen_address = params_.leader_http_listen_address.empty()
                                     ? absl::StrCat(HostOf(params_.leader.listen_address), ":0")
                                     : params_.leader_http_listen_address;
    http_params.cert_path = params_.leader.security.cert_path;
    http_params.key_path = params_.leader.security.key_path;
    dashboard = std::make_unique<http::HttpGateway>(
        &leader->app(), [server = leader.get()] { return server->RenderMetrics(); }, http_params);
    absl::StatusOr<int> http_port = dashboard->Start();
    if (!http_port.ok()) {
      if (params_.on_leadership_lost) {
        params_.on_leadership_lost(
            absl::StrCat("cannot serve the leader's dashboard: ", http_port.status().ToString()));
      }
      return;
    }
    const std::string http_host = HostOf(http_params.listen_address);
    dashboard_address =
        absl::StrCat(IsWildcardHost(http_host) ? HostOf(address) : http_host, ":", *http_port);
  }
  // With TLS even this replica's own public port goes through the leader port's checks: an
  // in-process call would skip the gate (no TLS, no auth metadata processor).
  proxy_.SetLeader(epoch, secure_ ? LeaderChannel(address)
                                  : leader->InProcessChannel(params_.leader.max_message_bytes));
  SetLeaderDashboard(dashboard_address);
  {
    absl::MutexLock lock(&leader_mutex_);
    leader_ = std::move(leader);
    leader_http_ = std::move(dashboard);
  }
  if (absl::Status published =
          leadership_->Publish(epoch, LeaseAddress(address, dashboard_address));
      !published.ok()) {
    if (params_.on_leadership_lost) params_.on_leadership_lost(std::string(published.message()));
    return;
  }
  Tell(absl::StrCat(
      "site '", params_.leadership.site, "': leading at epoch ", epoch,
      " (jobs recovered, dispatching); the other replicas relay to ", address,
      dashboard_address.empty() ? "" : absl::StrCat(", dashboard ", dashboard_address)));
}

std::shared_ptr<grpc::Channel> ReplicaServer::LeaderChannel(const std::string& address) const {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(params_.leader.max_message_bytes);
  arguments.SetMaxSendMessageSize(params_.leader.max_message_bytes);
  arguments.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, 100);
  arguments.SetInt(GRPC_ARG_MIN_RECONNECT_BACKOFF_MS, 100);
  arguments.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, 500);
  if (!secure_) {
    return grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), arguments);
  }
  // Only the replicas' own certificate is trusted (gRPC takes a root that is no CA as the end
  // of the chain); the leader's host must be one it names. No client certificate: the relay
  // key proves the replica.
  grpc::SslCredentialsOptions tls;
  tls.pem_root_certs = leader_certificate_pem_;
  return grpc::CreateCustomChannel(address, grpc::SslCredentials(tls), arguments);
}

void ReplicaServer::OnLeaderChanged(const storage::SiteLease& lease) {
  if (lease.holder == holder()) return;
  const auto [leader_port, dashboard] = SplitLeaseAddress(lease.address);
  SetLeaderDashboard(dashboard);
  if (leader_port.empty()) {
    proxy_.SetLeader(lease.epoch, nullptr);
    Tell(absl::StrCat("site '", params_.leadership.site, "': replica ", lease.holder,
                      " leads at epoch ", lease.epoch, " and is starting"));
    return;
  }
  proxy_.SetLeader(lease.epoch, LeaderChannel(leader_port));
  Tell(absl::StrCat("site '", params_.leadership.site, "': the leader is ", lease.holder, " at ",
                    leader_port, " (epoch ", lease.epoch, ")"));
}

void ReplicaServer::Shutdown() {
  if (server_ == nullptr || stopping_.exchange(true)) return;
  leadership_->Stop();
  if (http_relay_ != nullptr) http_relay_->Stop();
  proxy_.Close();
  if (front_door_ != nullptr) front_door_->Stop();
  server_->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(1));
  if (starter_.joinable()) starter_.join();
  std::unique_ptr<FleetServer> leader;
  std::unique_ptr<http::HttpGateway> dashboard;
  {
    absl::MutexLock lock(&leader_mutex_);
    leader = std::move(leader_);
    dashboard = std::move(leader_http_);
  }
  if (dashboard != nullptr) dashboard->Stop();
  if (leader != nullptr) {
    leader->Shutdown();
    // Handing over: the next replica need not wait for the lease to run out.
    (void)leases_->Release(params_.leadership.site, holder(), leading_epoch_.load());
  }
}

}  // namespace fleetnav::server
