#pragma once

#include <atomic>

#include "fleetnav/server/fleet_registry.hpp"
#include "fleetnav/server/job_service.hpp"
#include "fleetnav/server/rpc/agent_mailbox.hpp"
#include "fleetnav/v1/agent_service.grpc.pb.h"

namespace fleetnav::server {

/// gRPC edge of AgentService. One Connect stream per robot: the server sends its initial
/// metadata at once (so clients do not buffer for retries), expects a hello first
/// (InvalidArgument otherwise), answers with a welcome, then records telemetry and job events
/// until the agent hangs up, while a writer thread forwards the robot's outbox (assignments,
/// commands). A later connection with the same robot id replaces this one, which then ends
/// with FailedPrecondition. Thread-safe.
class AgentServiceImpl final : public v1::AgentService::Service {
 public:
  AgentServiceImpl(FleetRegistry* registry, JobService* jobs, AgentMailbox* mailbox,
                   const std::atomic<bool>* stopping)
      : registry_(registry), jobs_(jobs), mailbox_(mailbox), stopping_(stopping) {}

  grpc::Status Connect(
      grpc::ServerContext* context,
      grpc::ServerReaderWriter<v1::ServerMessage, v1::AgentMessage>* stream) override;

 private:
  FleetRegistry* registry_;
  JobService* jobs_;
  AgentMailbox* mailbox_;
  const std::atomic<bool>* stopping_;
};

}  // namespace fleetnav::server
