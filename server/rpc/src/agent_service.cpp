#include "fleetnav/server/rpc/agent_service.hpp"

#include <chrono>
#include <thread>

#include "absl/strings/str_cat.h"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/proto/job_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"

namespace fleetnav::server {

grpc::Status AgentServiceImpl::Connect(
    grpc::ServerContext* context,
    grpc::ServerReaderWriter<v1::ServerMessage, v1::AgentMessage>* stream) {
  stream->SendInitialMetadata();
  v1::AgentMessage message;
  if (!stream->Read(&message)) return grpc::Status::OK;
  if (message.payload_case() != v1::AgentMessage::kHello) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        "the first message on an agent stream must be `hello`");
  }
  absl::StatusOr<RobotIdentity> identity = FromProto(message.hello());
  if (!identity.ok()) return ToGrpcStatus(identity.status());
  const std::string robot_id = identity->robot_id;
  // Settle the jobs this robot held before it shows as online, so that the dispatcher cannot
  // hand it new work in between; its outbox is open before then too.
  std::shared_ptr<AgentOutbox> outbox = mailbox_->Open(robot_id);
  jobs_->OnRobotConnected(*identity, message.hello().resume_job_id());
  const uint64_t session = registry_->Connect(*identity);

  v1::ServerMessage welcome;
  welcome.mutable_welcome()->set_server_time_ns(
      std::chrono::duration_cast<std::chrono::nanoseconds>(
          std::chrono::steady_clock::now().time_since_epoch())
          .count());
  welcome.mutable_welcome()->set_telemetry_rate_hz(10.0);
  stream->Write(welcome);

  // Assignments and commands reach the robot through its outbox, written by this thread.
  std::thread writer([stream, outbox] {
    while (std::optional<v1::ServerMessage> next = outbox->Pop()) {
      if (!stream->Write(*next)) break;
    }
  });

  absl::Status status = absl::OkStatus();
  while (status.ok() && !stopping_->load() && !context->IsCancelled() && stream->Read(&message)) {
    switch (message.payload_case()) {
      case v1::AgentMessage::kTelemetry: {
        absl::StatusOr<Telemetry> telemetry = FromProto(message.telemetry());
        status = telemetry.ok() ? registry_->RecordTelemetry(robot_id, session, *telemetry)
                                : telemetry.status();
        if (status.ok()) jobs_->OnTelemetry(robot_id, *telemetry);
        break;
      }
      case v1::AgentMessage::kEvent: {
        absl::StatusOr<JobEvent> event = JobEventFromAgentEvent(message.event());
        if (event.ok()) {
          jobs_->OnRobotEvent(robot_id, *event);
        } else if (message.event().type() == v1::AgentEvent::TYPE_UNSPECIFIED) {
          status = event.status();
        }
        break;
      }
      case v1::AgentMessage::kHello:
        status = absl::InvalidArgumentError("hello: sent twice on one stream");
        break;
      case v1::AgentMessage::PAYLOAD_NOT_SET:
        status = absl::InvalidArgumentError("payload: empty agent message");
        break;
    }
  }
  mailbox_->Close(robot_id, outbox);
  writer.join();
  if (registry_->Disconnect(robot_id, session)) jobs_->OnRobotDisconnected(robot_id);
  return ToGrpcStatus(status);
}

}  // namespace fleetnav::server
