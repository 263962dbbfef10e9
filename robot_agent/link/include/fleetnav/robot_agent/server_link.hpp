#pragma once

#include <grpcpp/channel.h>
#include <grpcpp/client_context.h>

#include <atomic>
#include <deque>
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
};

/// The agent's AgentService.Connect stream to fleetnavd, on a thread of its own: says hello
/// (with the job it is executing, so the server can resume it), then forwards job events (never
/// dropped) before queued telemetry, and receives assignments and commands; on any failure it
/// reconnects with exponential back-off and says hello again. Nothing here blocks the control
/// loop. Thread-safe.
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

  std::unique_ptr<v1::AgentService::Stub> stub_;
  RobotIdentity identity_;
  ServerLinkParams params_;
  absl::Mutex mutex_;
  std::deque<Telemetry> queue_ ABSL_GUARDED_BY(mutex_);
  std::deque<JobEvent> events_ ABSL_GUARDED_BY(mutex_);
  std::deque<JobAssignment> assignments_ ABSL_GUARDED_BY(mutex_);
  std::vector<JobCommand> commands_ ABSL_GUARDED_BY(mutex_);
  std::string current_job_id_ ABSL_GUARDED_BY(mutex_);
  bool closing_ ABSL_GUARDED_BY(mutex_) = false;
  std::atomic<uint64_t> sent_{0};
  std::atomic<uint64_t> dropped_{0};
  std::atomic<int> connections_{0};
  std::thread thread_;
};

}  // namespace fleetnav::agent
