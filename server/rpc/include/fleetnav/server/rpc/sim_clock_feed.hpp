#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <thread>

#include "absl/status/status.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/v1/sim_service.grpc.pb.h"

namespace fleetnav::server {

/// Keeps a ManualClock at the simulator's time: it reads SimService.GetGroundTruth every
/// poll_period_s of wall time on its own thread, so that fleetnavd's stale and lost-robot
/// timeouts and pose history count simulated seconds in a simulated run (a run at 50× real
/// time then behaves as at 1×; a paused simulator stops the server's time). The clock never
/// goes backwards; its calendar starts at the simulation's (GroundTruth.start_unix_ms).
/// Thread-safe.
class SimClockFeed {
 public:
  SimClockFeed(const std::string& sim_address, ManualClock* clock, double poll_period_s = 0.05);
  ~SimClockFeed();
  SimClockFeed(const SimClockFeed&) = delete;
  SimClockFeed& operator=(const SimClockFeed&) = delete;

  /// Reads the simulator's time once — Unavailable naming the address when it does not
  /// answer within timeout_s — then follows it until Stop().
  absl::Status Start(double timeout_s = 10.0);
  void Stop();

 private:
  bool ReadOnce(double deadline_s);

  std::string address_;
  ManualClock* clock_;
  double poll_period_s_;
  std::unique_ptr<v1::SimService::Stub> stub_;
  bool calendar_set_ = false;  ///< by the first read (Start), before the thread runs
  std::atomic<bool> stopping_{false};
  std::thread thread_;
};

}  // namespace fleetnav::server
