#pragma once

#include <grpcpp/server_builder.h>

#include <atomic>
#include <memory>
#include <thread>
#include <vector>

#include "absl/synchronization/mutex.h"
#include "fleetnav/server/robot_sessions.hpp"
#include "fleetnav/server/rpc/access_gate.hpp"
#include "fleetnav/server/rpc/agent_mailbox.hpp"
#include "fleetnav/server/rpc/tick_barrier.hpp"
#include "fleetnav/v1/agent_service.grpc.pb.h"

namespace fleetnav::server {

class AgentConnection;

/// gRPC edge of AgentService on the async (completion-queue) API: `threads` completion queues,
/// each served by one thread, and a small state machine per robot stream, so thousands of robots
/// cost memory, not threads. A stream sends its initial metadata at once (so clients do not
/// buffer for retries), expects a hello first (InvalidArgument otherwise), answers with a
/// welcome once the robot is registered, then records telemetry and job events until the agent
/// hangs up, while the robot's outbox (assignments, commands) is written as it fills. A later
/// connection with the same robot id replaces this one, which then ends with
/// FailedPrecondition.
///
/// Why not the callback API: Debian's gRPC is built with assertions on, and then every
/// completion searches a list of all operations pending on its queue; the callback API puts
/// every stream on one queue, so at 5,000 robots that search was a fifth of the server's time.
/// Here each queue holds one pending read per stream of its own share.
///
/// Lifecycle: Register() before the server is built, Start() after, Shutdown() after the
/// server's Shutdown(). Thread-safe.
class AgentServiceImpl final {
 public:
  /// `gate` (may be null: no TLS) checks each hello's robot id against the stream's client
  /// certificate. `barrier` (may be null: no lockstep) takes in the streams whose hello asks for
  /// lockstep tick by tick.
  AgentServiceImpl(RobotSessions* sessions, AgentMailbox* mailbox, int threads,
                   AccessGate* gate = nullptr, TickBarrier* barrier = nullptr);
  ~AgentServiceImpl();
  AgentServiceImpl(const AgentServiceImpl&) = delete;
  AgentServiceImpl& operator=(const AgentServiceImpl&) = delete;

  /// Registers the service and adds its completion queues to `builder`.
  void Register(grpc::ServerBuilder* builder);
  /// Starts serving streams; call once, after the server was built.
  void Start();
  /// Ends the completion queues and joins their threads; call after the server's Shutdown()
  /// (which ends the open streams). Idempotent.
  void Shutdown();
  /// Telemetry messages accepted since the start.
  uint64_t telemetry_messages() const {
    return telemetry_messages_.load(std::memory_order_relaxed);
  }

 private:
  friend class AgentConnection;
  void Serve(grpc::ServerCompletionQueue* cq);
  /// Waits for the next call on `cq` unless shutting down.
  void Accept(grpc::ServerCompletionQueue* cq);
  void ConnectionGone();

  RobotSessions* sessions_;  ///< the session rules; this edge only carries them
  AgentMailbox* mailbox_;
  AccessGate* const gate_;      ///< null without TLS
  TickBarrier* const barrier_;  ///< null: lockstep streams are taken in as they come
  const int thread_count_;
  v1::AgentService::AsyncService service_;
  std::vector<std::unique_ptr<grpc::ServerCompletionQueue>> cqs_;
  std::vector<std::thread> threads_;
  bool shut_down_ = false;
  std::atomic<bool> stopping_{false};
  std::atomic<uint64_t> telemetry_messages_{0};
  absl::Mutex live_mutex_;
  int live_connections_ ABSL_GUARDED_BY(live_mutex_) = 0;  ///< including calls awaited
};

}  // namespace fleetnav::server
