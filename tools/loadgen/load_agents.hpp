#pragma once

#include <grpcpp/channel.h>
#include <grpcpp/client_context.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "fleetnav/v1/agent_service.grpc.pb.h"

namespace fleetnav::loadgen {

/// One simulated robot's AgentService.Connect stream on gRPC's callback API: says hello, then
/// sends one telemetry message whenever Send() is called and the previous write has finished
/// (a write still in flight means the server is behind: the tick is counted as skipped).
/// Thread-safe: Send() from the pacing thread, reactions on gRPC's threads.
class LoadAgent final : public grpc::ClientBidiReactor<v1::AgentMessage, v1::ServerMessage> {
 public:
  LoadAgent(v1::AgentService::Stub* stub, std::string robot_id);
  /// Sends a telemetry message due at `due_ns` (steady clock); false if skipped.
  bool Send(int64_t due_ns, uint64_t sequence);
  void Cancel() { context_.TryCancel(); }
  bool ready() const { return hello_done_.load(); }
  bool done() const { return done_.load(); }
  /// Latencies (ms) from due time to write completion, taken since the last call.
  std::vector<double> TakeLatencies();
  uint64_t completed() const { return completed_.load(); }

  void OnWriteDone(bool ok) override;
  void OnReadDone(bool ok) override;
  void OnDone(const grpc::Status& status) override;

 private:
  grpc::ClientContext context_;
  std::string robot_id_;
  v1::AgentMessage hello_;
  v1::AgentMessage out_;
  v1::ServerMessage in_;
  std::atomic<bool> writing_{true};
  std::atomic<bool> hello_done_{false};
  std::atomic<bool> done_{false};
  std::atomic<uint64_t> completed_{0};
  int64_t due_ns_ = 0;
  std::mutex latencies_mutex_;
  std::vector<double> latencies_ms_;
};

int64_t SteadyNowNs();

}  // namespace fleetnav::loadgen
