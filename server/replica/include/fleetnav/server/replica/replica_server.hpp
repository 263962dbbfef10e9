#pragma once

#include <grpcpp/server.h>

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/server/http/http_gateway.hpp"
#include "fleetnav/server/http/http_relay.hpp"
#include "fleetnav/server/replica/leader_proxy.hpp"
#include "fleetnav/server/replica/site_leadership.hpp"
#include "fleetnav/server/rpc/fleet_server.hpp"
#include "fleetnav/server/rpc/health_service.hpp"
#include "fleetnav/server/rpc/tls_front_door.hpp"
#include "fleetnav/storage/postgres/pg_database.hpp"
#include "fleetnav/storage/postgres/pg_site_leases.hpp"

namespace fleetnav::server {

struct ReplicaParams {
  /// The leader's server as it runs once this replica leads: its db_path must be a
  /// postgresql:// URI the replicas share, and its listen_address is the leader port the
  /// other replicas relay to (port 0: any). Its security files, when given, make every port
  /// of the replica TLS with the same certificate, robot CA and tokens (docs/security.md).
  FleetServerParams leader;
  /// The public port robots and operators use; every replica serves it.
  std::string listen_address = "127.0.0.1:50051";
  /// How the other replicas reach this one's leader port; empty: the leader port's host with
  /// the bound port (refused when that host is a wildcard address). With TLS the server
  /// certificate must name its host.
  std::string advertise_address;
  /// The dashboard, its API and /metrics (HttpRelay to the leader's dashboard) on host:port;
  /// empty: none. HTTPS with the TLS files.
  std::string http_listen_address;
  /// Where the leader serves its dashboard to the replicas' relays (an HttpGateway over its
  /// FleetServer), with http_listen_address; empty: the leader port's host, any port.
  std::string leader_http_listen_address;
  SiteLeadershipParams leadership;
  /// Told what happens (elected, leader changed), for the log.
  std::function<void(const std::string&)> on_event;
  /// Told once that this replica lost the leadership it held; it must end the process at once
  /// (a supervisor restarts it as a follower). Its store writes nothing more in any case.
  std::function<void(const std::string&)> on_leadership_lost;
  absl::Status Validate() const;
};

/// One fleetnavd of several that share a PostgreSQL database and serve one site. Every replica
/// serves the same public port — FleetService, AccessService, AgentService and health — and
/// relays each call (LeaderProxy) to the site's one leader, elected through the site lease
/// (SiteLeadership). The replica that wins the lease starts a whole FleetServer on its leader
/// port, with its store fenced by the lease epoch: recovery of unfinished jobs, dispatching,
/// traffic coordination and the robots' streams all run there, so the single-server logic
/// holds unchanged, and every replica sees every robot (WatchFleet is relayed too). Its own
/// public port reaches it in-process (over TLS when serving TLS, see below). When the leader
/// dies the others take over once its lease runs out; robots whose relayed streams end
/// reconnect through any replica and resume their jobs. With TLS (docs/security.md,
/// "Replicas") the public port verifies robot certificates against the robot CA and relays,
/// with each call, the robot id it verified and the replicas' relay key; the leader port checks
/// both, and every token with the leader's live AccessPolicy; each replica reaches the leader
/// port over TLS trusting only the server certificate they share (the leader itself too, since
/// an in-process call skips the checks). With http_listen_address every replica serves the
/// dashboard by relaying to the leader's, whose address the lease carries after the leader
/// port's (" http=HOST:PORT"). Start once; Shutdown ends the streams.
class ReplicaServer {
 public:
  explicit ReplicaServer(ReplicaParams params);
  ~ReplicaServer();
  ReplicaServer(const ReplicaServer&) = delete;
  ReplicaServer& operator=(const ReplicaServer&) = delete;

  /// Opens the lease store (migrating or refusing the schema as the leader would), starts the
  /// public port and the election; returns the public port.
  absl::StatusOr<int> Start();
  void Shutdown();
  const std::string& holder() const { return leadership_->holder(); }
  /// The HTTP port (0 without http_listen_address); after Start().
  int http_port() const { return http_port_; }
  bool secure() const { return secure_; }
  std::string store_description() const { return lease_db_ ? lease_db_->Describe() : ""; }

 private:
  void OnElected(int64_t epoch);
  void OnLeaderChanged(const storage::SiteLease& lease);
  /// Starts the leader's server (on the starter thread).
  void Lead(int64_t epoch);
  /// A channel to the leader port at `address`: over TLS pinning the server certificate, or
  /// plaintext.
  std::shared_ptr<grpc::Channel> LeaderChannel(const std::string& address) const;
  std::string LeaderDashboard() const {
    absl::MutexLock lock(&dashboard_mutex_);
    return leader_dashboard_;
  }
  void SetLeaderDashboard(std::string address) {
    absl::MutexLock lock(&dashboard_mutex_);
    leader_dashboard_ = std::move(address);
  }
  void Tell(const std::string& what) const {
    if (params_.on_event) params_.on_event(what);
  }

  ReplicaParams params_;
  SystemClock clock_;
  std::unique_ptr<storage::PgDatabase> lease_db_;
  std::unique_ptr<storage::PgSiteLeases> leases_;
  std::unique_ptr<SiteLeadership> leadership_;
  LeaderProxy proxy_;
  std::unique_ptr<HealthServiceImpl> health_;
  std::unique_ptr<TlsFrontDoor> front_door_;  ///< the public TLS port's acceptor; null without TLS
  std::unique_ptr<grpc::Server> server_;
  bool secure_ = false;
  std::string leader_certificate_pem_;  ///< the server certificate the replicas pin
  std::unique_ptr<http::HttpRelay> http_relay_;
  int http_port_ = 0;
  mutable absl::Mutex dashboard_mutex_;
  std::string leader_dashboard_ ABSL_GUARDED_BY(dashboard_mutex_);  ///< host:port, "" unknown
  std::atomic<bool> stopping_{false};
  std::atomic<int64_t> leading_epoch_{0};
  absl::Mutex leader_mutex_;
  std::unique_ptr<FleetServer> leader_ ABSL_GUARDED_BY(leader_mutex_);
  std::unique_ptr<http::HttpGateway> leader_http_ ABSL_GUARDED_BY(leader_mutex_);
  std::thread starter_;
};

}  // namespace fleetnav::server
