#pragma once

#include <atomic>

#include "fleetnav/server/fleet_registry.hpp"
#include "fleetnav/server/job_service.hpp"
#include "fleetnav/server/rpc/agent_mailbox.hpp"
#include "fleetnav/v1/agent_service.grpc.pb.h"

namespace fleetnav::server {

/// gRPC edge of AgentService on the callback API: one reactor per robot stream, no thread per
/// stream, so thousands of robots cost memory, not threads. A stream sends its initial metadata
/// at once (so clients do not buffer for retries), expects a hello first (InvalidArgument
/// otherwise), answers with a welcome, then records telemetry and job events until the agent
/// hangs up, while the robot's outbox (assignments, commands) is written as it fills. A later
/// connection with the same robot id replaces this one, which then ends with
/// FailedPrecondition. Thread-safe.
class AgentServiceImpl final : public v1::AgentService::CallbackService {
 public:
  AgentServiceImpl(FleetRegistry* registry, JobService* jobs, AgentMailbox* mailbox)
      : registry_(registry), jobs_(jobs), mailbox_(mailbox) {}

  grpc::ServerBidiReactor<v1::AgentMessage, v1::ServerMessage>* Connect(
      grpc::CallbackServerContext* context) override;

 private:
  FleetRegistry* registry_;
  JobService* jobs_;
  AgentMailbox* mailbox_;
};

}  // namespace fleetnav::server
