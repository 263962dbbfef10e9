#pragma once

#include <grpcpp/server.h>

#include <memory>
#include <string>
#include <thread>

#include "absl/status/statusor.h"
#include "fleetnav/sim/lockstep.hpp"
#include "fleetnav/sim/sim_service.hpp"
#include "fleetnav/sim/simulation.hpp"

namespace fleetnav::sim {

struct SimServerParams {
  std::string listen_address = "127.0.0.1:50061";  ///< port 0 picks a free port
  SimulationParams simulation;
  LockstepParams lockstep;
  /// The calendar at sim time 0 (ms since 1970-01-01 UTC), told to fleetnavd through
  /// GroundTruth; 0: none (fleetnavd then stamps from its own start).
  int64_t start_unix_ms = 0;
};

/// fleetnav-sim as a library: a Simulation of a world, its Lockstep loop on a thread of its
/// own, and SimService on a socket. Used by main() and by integration tests.
class SimServer {
 public:
  SimServer(WorldDescription world, SimServerParams params);
  ~SimServer();

  /// Spawns the world's robots, starts serving and ticking; returns the bound port.
  absl::StatusOr<int> Start();
  /// Stops the loop and the server; safe to call twice.
  void Shutdown();
  /// Blocks until the lockstep loop ends (Shutdown or max sim time).
  void WaitForLoop();
  Lockstep& lockstep() { return *lockstep_; }

 private:
  WorldDescription world_;
  SimServerParams params_;
  std::unique_ptr<Simulation> simulation_;
  std::unique_ptr<Lockstep> lockstep_;
  std::unique_ptr<SimServiceImpl> service_;
  std::unique_ptr<grpc::Server> server_;
  std::thread loop_;
  bool shut_down_ = false;
};

}  // namespace fleetnav::sim
