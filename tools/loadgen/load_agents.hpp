#pragma once

#include <grpcpp/channel.h>
#include <grpcpp/client_context.h>
#include <grpcpp/completion_queue.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "fleetnav/v1/agent_service.grpc.pb.h"
#include "load_tls.hpp"

namespace fleetnav::loadgen {

int64_t SteadyNowNs();

/// When, within each period, the agent at `index` of `agents` sends: the agents' messages are
/// spread evenly over the period, in index order. 0 <= result < period_ns.
int64_t DueOffsetNs(int index, int agents, int64_t period_ns);

/// What one worker measured.
struct WorkerReport {
  int connected = 0;           ///< agents the server welcomed
  uint64_t scheduled = 0;      ///< telemetry messages that fell due
  uint64_t skipped = 0;        ///< due while the agent's previous write was still in flight
  uint64_t delivered = 0;      ///< writes completed before the measured window closed
  std::vector<double> lag_ms;  ///< due time -> write completion, per delivered message
  /// Each StopUpdate with a stop in force that an agent received: (agent index, steady ns).
  std::vector<std::pair<int, int64_t>> stops_heard;
};

struct WorkerParams {
  LoadTarget target;         ///< on TLS every agent has a connection (and certificate) of its own
  int agents = 0;            ///< agents in the whole run (for the pacing spread)
  std::vector<int> indices;  ///< this worker's agents, ascending
  int streams_per_connection = 250;  ///< agent streams multiplexed on one HTTP/2 connection
  int first_channel_index = 0;       ///< distinguishes this worker's connections
  /// Agents with an index below this advertise "straight", so jobs on the loadgen routes are
  /// assigned to them (each keeps its job: it never reports on it).
  int capable_agents = 0;
};

/// A set of simulated robots driven by one thread on the async (completion-queue) API: each
/// agent has one AgentService.Connect stream that says hello, waits for the welcome, then sends one
/// telemetry message each time it falls due while its previous write has completed (otherwise the
/// tick is counted as skipped: the server is behind and flow control holds the write). The thread
/// alone paces, writes and reaps completions of its own completion queue, so workers share nothing
/// and the pacing of N agents spreads over as many threads as there are workers. Not thread-safe
/// except where noted; the owner calls Connect(), then Run(), then Stop() from one thread.
class LoadWorker {
 public:
  explicit LoadWorker(WorkerParams params);
  ~LoadWorker();
  LoadWorker(const LoadWorker&) = delete;
  LoadWorker& operator=(const LoadWorker&) = delete;

  /// Opens every stream and waits until the server has welcomed every agent (so it has
  /// registered them all) or `deadline_ns` passes. Returns the number of agents welcomed.
  int Connect(int64_t deadline_ns);
  /// Keeps the streams serviced (reads, late completions) until `until_ns`.
  void Idle(int64_t until_ns);
  /// Sends telemetry from `start_ns` to `end_ns` at `period_ns` per agent, then keeps reaping
  /// completions until `drain_until_ns`; only writes completed by then count as delivered.
  void Run(int64_t start_ns, int64_t end_ns, int64_t period_ns, int64_t drain_until_ns);
  /// Cancels every stream and waits until gRPC has returned all of them.
  void Stop();
  WorkerReport TakeReport();

 private:
  struct Agent;
  enum class Op : uintptr_t { kStart = 0, kWrite = 1, kRead = 2, kFinish = 3 };
  static void* Tag(Agent* agent, Op op);
  /// Waits for one completion until `deadline_ns` and handles it; false on timeout.
  bool Poll(int64_t deadline_ns, bool measuring);
  void Handle(Agent* agent, Op op, bool ok, bool measuring);
  void Send(Agent* agent, int64_t due_ns, uint64_t sequence);
  void MaybeFinish(Agent* agent);

  WorkerParams params_;
  grpc::CompletionQueue cq_;
  std::vector<std::shared_ptr<grpc::Channel>> channels_;
  std::vector<std::unique_ptr<v1::AgentService::Stub>> stubs_;
  std::vector<std::unique_ptr<Agent>> agents_;
  int ready_ = 0;
  bool stopped_ = false;
  WorkerReport report_;
};

}  // namespace fleetnav::loadgen
