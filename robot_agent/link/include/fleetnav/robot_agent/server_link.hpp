#pragma once

#include <grpcpp/channel.h>
#include <grpcpp/client_context.h>

#include <atomic>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <thread>

#include "absl/synchronization/mutex.h"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/robot_agent/job_channel.hpp"
#include "fleetnav/robot_agent/telemetry_sink.hpp"
#include "fleetnav/v1/agent_service.grpc.pb.h"

namespace fleetnav::agent {

struct ServerLinkParams {
  double initial_backoff_s = 0.2;
  double max_backoff_s = 5.0;
  size_t max_queued = 256;  ///< telemetry kept while disconnected; the oldest is dropped
  /// Take part in a simulated run's lockstep (see ServerLink).
  bool lockstep = false;
};

/// The agent's AgentService.Connect stream to fleetnavd, on a thread of its own: says hello
/// (with the job it is executing, so the server can resume it), then forwards job events (never
/// dropped) before queued telemetry, and receives assignments and commands; on any failure it
/// reconnects with exponential back-off and says hello again. Nothing here blocks the control
/// loop, except BeginTick and EndTick in lockstep: then each tick ends with TickDone, the next
/// frame begins once the server's TickAck for it has come (EndTick itself waits for it only
/// before a hold), what the server sends is handed to the agent only once the TickAck that
/// follows it has come (so a message reaches the agent at the same tick in every run), and what
/// the agent sent is kept until a TickAck covers it and sent again on the next session if none
/// does. Thread-safe.
class ServerLink final : public TelemetrySink, public JobChannel {
 public:
  ServerLink(std::shared_ptr<grpc::Channel> channel, RobotIdentity identity,
             ServerLinkParams params = {});
  ~ServerLink() override;

  void Publish(const Telemetry& telemetry) override;
  std::optional<JobAssignment> TakeAssignment() override;
  std::vector<JobCommand> TakeCommands() override;
  void ReportEvent(const JobEvent& event) override;
  void SetCurrentJob(const std::string& job_id) override;
  void BeginTick() override;
  void EndTick(const SensorFrame& frame) override;
  std::vector<RobotStop> Stops() override;
  std::optional<ToldZones> Zones(const std::string& map_id) override;
  bool HearsServer() override;
  /// Sends what is queued (waiting up to timeout_s), then closes the stream.
  void Close(double timeout_s = 2.0);

  uint64_t sent() const { return sent_.load(); }
  uint64_t dropped() const { return dropped_.load(); }
  int connections() const { return connections_.load(); }

 private:
  void RunLoop();
  /// One connection: hello, then telemetry until failure or close.
  void RunSession();
  void OnServerMessage(const v1::ServerMessage& message);
  void ApplyServerMessage(const v1::ServerMessage& message) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// The next message to send, or nullopt when there is none: events, telemetry, then (in
  /// lockstep) the tick's TickDone.
  std::optional<v1::AgentMessage> NextMessage() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// After `message` was written: drops it from its queue (and keeps it until acknowledged).
  void MessageWritten(const v1::AgentMessage& message) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// A session ended: what the server sent is handed over, nothing waits for a TickAck, and
  /// what was sent without one goes back to the front of its queue — so the next session sends
  /// the same messages in the same order whenever this one noticed that it had ended.
  void SessionEnded() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void DropOldTelemetry() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  /// A message sent in lockstep, kept until a TickAck covers it.
  struct Unacknowledged {
    std::optional<uint64_t> tick;  ///< the TickDone sent after it
    std::optional<JobEvent> event;
    std::optional<Telemetry> telemetry;
  };

  std::unique_ptr<v1::AgentService::Stub> stub_;
  RobotIdentity identity_;
  ServerLinkParams params_;
  absl::Mutex mutex_;
  /// Signalled on every change one of the waiters may wait for: the writer, EndTick, Close and
  /// the back-off between sessions.
  absl::CondVar changed_;
  std::deque<Telemetry> queue_ ABSL_GUARDED_BY(mutex_);
  std::deque<JobEvent> events_ ABSL_GUARDED_BY(mutex_);
  std::deque<JobAssignment> assignments_ ABSL_GUARDED_BY(mutex_);
  std::vector<JobCommand> commands_ ABSL_GUARDED_BY(mutex_);
  std::vector<RobotStop> stops_ ABSL_GUARDED_BY(mutex_);            ///< in force, as last told
  std::map<std::string, ToldZones> zones_ ABSL_GUARDED_BY(mutex_);  ///< by map, as last told
  /// The live session's welcome was handed over (false from the session's end on).
  bool welcomed_ ABSL_GUARDED_BY(mutex_) = false;
  std::string current_job_id_ ABSL_GUARDED_BY(mutex_);
  bool closing_ ABSL_GUARDED_BY(mutex_) = false;
  // Lockstep only:
  std::vector<v1::ServerMessage> held_ ABSL_GUARDED_BY(mutex_);  ///< until the next TickAck
  std::deque<Unacknowledged> unacknowledged_ ABSL_GUARDED_BY(mutex_);
  std::optional<v1::TickDone> tick_done_ ABSL_GUARDED_BY(mutex_);
  std::optional<uint64_t> acknowledged_tick_ ABSL_GUARDED_BY(mutex_);
  bool session_live_ ABSL_GUARDED_BY(mutex_) = false;
  /// The last tick ended while no session was live: the next session's hello says the server
  /// must not wait for this stream at that tick or before.
  std::optional<uint64_t> last_tick_alone_ ABSL_GUARDED_BY(mutex_);
  /// The tick ended last in a live session, and that session: BeginTick waits for its TickAck.
  struct AwaitedAck {
    uint64_t session = 0;
    uint64_t tick = 0;
  };
  std::optional<AwaitedAck> awaited_ack_ ABSL_GUARDED_BY(mutex_);
  /// Waits, if a tick is awaited, until its session ended or the server acknowledged it.
  void AwaitAck() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  uint64_t session_ ABSL_GUARDED_BY(mutex_) = 0;
  std::atomic<uint64_t> sent_{0};
  std::atomic<uint64_t> dropped_{0};
  std::atomic<int> connections_{0};
  std::thread thread_;
};

}  // namespace fleetnav::agent
