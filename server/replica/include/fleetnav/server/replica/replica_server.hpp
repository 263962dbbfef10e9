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
#include "fleetnav/server/replica/leader_proxy.hpp"
#include "fleetnav/server/replica/site_leadership.hpp"
#include "fleetnav/server/rpc/fleet_server.hpp"
#include "fleetnav/server/rpc/health_service.hpp"
#include "fleetnav/storage/postgres/pg_database.hpp"
#include "fleetnav/storage/postgres/pg_site_leases.hpp"

namespace fleetnav::server {

struct ReplicaParams {
  /// The leader's server as it runs once this replica leads: its db_path must be a
  /// postgresql:// URI the replicas share, and its listen_address is the leader port the
  /// other replicas relay to (port 0: any).
  FleetServerParams leader;
  /// The public port robots and operators use; every replica serves it.
  std::string listen_address = "127.0.0.1:50051";
  /// How the other replicas reach this one's leader port; empty: the leader port's host with
  /// the bound port (refused when that host is a wildcard address).
  std::string advertise_address;
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
/// public port reaches it in-process. When the leader dies the others take over once its
/// lease runs out; robots whose relayed streams end reconnect through any replica and resume
/// their jobs. Start once; Shutdown ends the streams.
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
  std::string store_description() const { return lease_db_ ? lease_db_->Describe() : ""; }

 private:
  void OnElected(int64_t epoch);
  void OnLeaderChanged(const storage::SiteLease& lease);
  /// Starts the leader's server (on the starter thread).
  void Lead(int64_t epoch);
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
  std::unique_ptr<grpc::Server> server_;
  std::atomic<bool> stopping_{false};
  std::atomic<int64_t> leading_epoch_{0};
  absl::Mutex leader_mutex_;
  std::unique_ptr<FleetServer> leader_ ABSL_GUARDED_BY(leader_mutex_);
  std::thread starter_;
};

}  // namespace fleetnav::server
