#pragma once

#include <sys/types.h>

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "load_agents.hpp"

// fleetnav-loadgen's operators: the site they prepare, the jobs they submit and watch (in a
// process of their own), and the idle watch streams.

namespace fleetnav::loadgen {

/// What the operators' site holds, beyond a small map and a one-action route.
struct SiteOptions {
  bool large = false;  ///< a 100,000-marker set, and a 10,000-action route for the jobs
  int big_map_mb = 0;  ///< a second map of this many MB, with goal jobs submitted on it
};

struct OperatorReport {
  std::vector<double> submit_ms;
  std::vector<double> dispatch_ms;    ///< submit -> ASSIGNED event, for watched jobs
  std::vector<double> big_submit_ms;  ///< goal jobs on the big map
  uint64_t submit_errors = 0;
  uint64_t watches = 0;
};

/// How the operators behave.
struct OperatorOptions {
  int submitters = 2;
  double rate_hz = 20.0;
  int watch_every = 10;         ///< every N-th job is watched
  bool until_assigned = false;  ///< watch until ASSIGNED (capable agents exist), else 1st event
  /// A submission refused or lost (a replica killed, a failover) is sent again with the same
  /// idempotency key until it is acknowledged or this much time passed (0: never again).
  double retry_s = 0.0;
  /// Each acknowledged job appended as "idempotency_key job_id" ("": none).
  std::string acked_path;
  SiteOptions site;
};

/// A map and a route for the submitters' jobs (and what `site` asks for).
bool PrepareRoute(v1::FleetService::Stub* fleet, const SiteOptions& site);

/// M operators each submitting jobs at `rate_hz` (and watching every tenth job until its first
/// event) until `stop` is set.
OperatorReport RunOperators(const LoadTarget& server, const OperatorOptions& options,
                            const std::atomic<bool>& stop);

/// The operators run in a child process, as real operators do: blocking calls of a few threads
/// starve when they share gRPC's pollers with thousands of busy agent streams in one process,
/// and then the loadgen, not the server, would be measured. Protocol: the child prepares the
/// route and writes 'R' (or 'E'); the parent writes 'G' to start, then closes its end to stop;
/// the child answers with its report as JSON and exits. Forked before any gRPC or thread exists.
class OperatorProcess {
 public:
  /// Forks the operators' process, which prepares the site; false when it could not.
  bool Start(const LoadTarget& server, const OperatorOptions& options);
  /// The operators begin submitting.
  void Go();
  /// Stops them and returns what they measured.
  OperatorReport Stop();

 private:
  static int Child(const LoadTarget& server, const OperatorOptions& options, int in, int out);

  pid_t pid_ = -1;
  int to_child_ = -1;
  int from_child_ = -1;
};

/// Idle WatchJob streams on one job that stays queued (its route has a turn, which no loadgen
/// agent advertises) and as many idle WatchFleet streams, 100 to a connection, each read up to its
/// first message and then left open until the run ends.
class IdleWatchers {
 public:
  /// Opens `count` WatchJob and `count` WatchFleet streams (nothing when the job cannot be
  /// submitted).
  void Open(const LoadTarget& server, int count);
  /// How many streams answered their first message.
  int open() const { return open_; }
  ~IdleWatchers();

 private:
  struct Stream {
    grpc::ClientContext context;
    std::unique_ptr<grpc::ClientReader<v1::JobEvent>> job;
    std::unique_ptr<grpc::ClientReader<v1::FleetUpdate>> fleet;
  };
  std::vector<std::unique_ptr<v1::FleetService::Stub>> stubs_;
  std::vector<std::unique_ptr<Stream>> streams_;
  int open_ = 0;
};

}  // namespace fleetnav::loadgen
