#pragma once

#include <grpcpp/server.h>

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/synchronization/notification.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/server/fleet_app.hpp"
#include "fleetnav/server/rpc/access_gate.hpp"
#include "fleetnav/server/rpc/access_service.hpp"
#include "fleetnav/server/rpc/agent_mailbox.hpp"
#include "fleetnav/server/rpc/agent_service.hpp"
#include "fleetnav/server/rpc/fleet_service.hpp"
#include "fleetnav/server/rpc/server_metrics.hpp"
#include "fleetnav/server/rpc/server_security.hpp"
#include "fleetnav/server/rpc/sim_clock_feed.hpp"
#include "fleetnav/server/rpc/tick_barrier.hpp"
#include "fleetnav/server/rpc/tls_front_door.hpp"
#include "fleetnav/server/rpc/watch_hub.hpp"

namespace fleetnav::server {

/// The app's parameters (store, wings, loops, log callbacks; those the server sets itself —
/// authorization, file tokens, metrics and watch callbacks — are overwritten) and the gRPC
/// server's own.
struct FleetServerParams : FleetAppParams {
  std::string listen_address = "127.0.0.1:50051";  ///< port 0 picks a free port
  int max_message_bytes = 64 << 20;                ///< largest request accepted (a 8k×8k map fits)
  /// Threads (each with its own completion queue) serving the robots' streams.
  int agent_stream_threads = 2;
  /// A SimService address: take time from the simulator (fleetnavd --clock sim); "": the
  /// system clock.
  std::string sim_clock_address;
  /// TLS and credentials; all empty: plaintext without authentication (fleetnavd only allows
  /// that with --insecure).
  ServerSecurityFiles security;
  /// With TLS: also take the calls fleetnavd replicas relay (the leader of replicas, see
  /// AccessGate and replica_relay.hpp); they prove themselves with the relay key of this
  /// server's private key.
  bool accept_replica_relays = false;
  absl::Status Validate() const;
};

/// fleetnavd as a library: the gRPC server over a FleetApp (which opens the store, recovers
/// robots and unfinished jobs and runs the dispatcher and housekeeping loops). It picks the
/// clock (the system's or the simulator's), loads TLS and tokens, builds FleetService,
/// AgentService and AccessService with health checking and reflection over the app, and serves
/// on a socket. Used by main() and by integration tests (real gRPC over loopback). Start once;
/// Shutdown() ends open streams within a second.
class FleetServer {
 public:
  explicit FleetServer(FleetServerParams params);
  ~FleetServer();

  /// Opens the database and starts serving; returns the bound port.
  absl::StatusOr<int> Start();
  void Shutdown();
  void Wait();
  /// A channel to this server inside the process (no socket), after Start().
  std::shared_ptr<grpc::Channel> InProcessChannel(int max_message_bytes);
  /// The dispatcher's passes that assigned jobs, and those that assigned exactly one (the
  /// replanning latency when a job is added); call after Shutdown().
  PassFigures assigning_passes() const;
  PassFigures one_job_passes() const;
  /// The same passes in the dispatcher thread's CPU time.
  PassFigures one_job_pass_cpu() const;
  /// Traffic coordination's searches in the CPU time of their own thread.
  PassFigures traffic_search_cpu() const;
  /// The Prometheus text exposition of the server's metrics now (docs/metrics.md).
  std::string RenderMetrics() const;
  /// Calls the TLS gate admitted and refused so far (all zero without TLS).
  AccessCounts access_counts() const;
  bool secure() const { return access_gate_ != nullptr; }
  /// The store's engine and place ("SQLite file fleet.db", "PostgreSQL database d at h:p"),
  /// never a password; call after Start().
  std::string store_description() const { return app_ != nullptr ? app_->store_description() : ""; }
  /// The use cases this server serves, for the sibling edges (the HTTP port); after Start().
  FleetApp& app() { return *app_; }

 private:
  FleetServerParams params_;
  SystemClock system_clock_;
  ManualClock sim_clock_;
  const Clock* clock_;  ///< the system clock, or the simulator's with sim_clock_address
  std::unique_ptr<SimClockFeed> sim_clock_feed_;
  std::atomic<bool> stopping_{false};
  AgentMailbox mailbox_;
  std::unique_ptr<FleetApp> app_;
  /// Lockstep streams, tick by tick (then it drives the clock, the dispatcher and housekeeping).
  std::unique_ptr<TickBarrier> barrier_;
  std::shared_ptr<AccessGate> access_gate_;   ///< null without TLS
  std::unique_ptr<TlsFrontDoor> front_door_;  ///< the TLS port's acceptor; null without TLS
  ServerMetrics metrics_;
  std::unique_ptr<grpc::Service> health_service_;
  std::unique_ptr<FleetServiceImpl> fleet_service_;
  std::unique_ptr<AccessServiceImpl> access_service_;
  std::unique_ptr<AgentServiceImpl> agent_service_;
  std::unique_ptr<WatchHub> watch_hub_;
  std::unique_ptr<grpc::Server> server_;
};

}  // namespace fleetnav::server
