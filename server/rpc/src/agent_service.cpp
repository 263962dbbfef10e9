#include "fleetnav/server/rpc/agent_service.hpp"

#include <chrono>

#include "absl/strings/str_cat.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/proto/job_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"

namespace fleetnav::server {
namespace {

/// One robot's stream. Reads run one after another (each OnReadDone starts the next); writes
/// come from the outbox, one at a time; Finish() is called once, after the last write.
class AgentConnection final : public grpc::ServerBidiReactor<v1::AgentMessage, v1::ServerMessage> {
 public:
  AgentConnection(FleetRegistry* registry, JobService* jobs, AgentMailbox* mailbox)
      : registry_(registry), jobs_(jobs), mailbox_(mailbox) {
    StartSendInitialMetadata();
    StartRead(&in_);
  }

  void OnReadDone(bool ok) override {
    if (!ok) {  // the agent hung up (or the call was cancelled)
      End(absl::OkStatus());
      return;
    }
    absl::Status status = hello_seen_ ? Handle(in_) : Hello(in_);
    if (!status.ok()) {
      End(status);
      return;
    }
    StartRead(&in_);
  }

  void OnWriteDone(bool ok) override {
    {
      absl::MutexLock lock(&mutex_);
      writing_ = false;
      if (!ok) broken_ = true;
    }
    PumpWrites();
  }

  void OnDone() override {
    if (outbox_ != nullptr) mailbox_->Close(robot_id_, outbox_);
    if (hello_seen_ && registry_->Disconnect(robot_id_, session_)) {
      jobs_->OnRobotDisconnected(robot_id_);
    }
    delete this;
  }

 private:
  absl::Status Hello(const v1::AgentMessage& message) {
    if (message.payload_case() != v1::AgentMessage::kHello) {
      return absl::InvalidArgumentError("the first message on an agent stream must be `hello`");
    }
    absl::StatusOr<RobotIdentity> identity = FromProto(message.hello());
    if (!identity.ok()) return identity.status();
    robot_id_ = identity->robot_id;
    hello_seen_ = true;
    v1::ServerMessage welcome;
    welcome.mutable_welcome()->set_server_time_ns(
        std::chrono::duration_cast<std::chrono::nanoseconds>(
            std::chrono::steady_clock::now().time_since_epoch())
            .count());
    welcome.mutable_welcome()->set_telemetry_rate_hz(10.0);
    // Settle the jobs this robot held before it shows as online, so that the dispatcher cannot
    // hand it new work in between; its outbox is open (welcome first) before then too.
    outbox_ = mailbox_->Open(robot_id_, [this] { PumpWrites(); });
    outbox_->Push(std::move(welcome));
    jobs_->OnRobotConnected(*identity, message.hello().resume_job_id());
    session_ = registry_->Connect(*identity);
    {
      // Writing starts only now: whoever reads the welcome finds the robot registered.
      absl::MutexLock lock(&mutex_);
      registered_ = true;
    }
    PumpWrites();
    return absl::OkStatus();
  }

  absl::Status Handle(const v1::AgentMessage& message) {
    switch (message.payload_case()) {
      case v1::AgentMessage::kTelemetry: {
        absl::StatusOr<Telemetry> telemetry = FromProto(message.telemetry());
        if (!telemetry.ok()) return telemetry.status();
        absl::Status recorded = registry_->RecordTelemetry(robot_id_, session_, *telemetry);
        if (recorded.ok()) jobs_->OnTelemetry(robot_id_, *telemetry);
        return recorded;
      }
      case v1::AgentMessage::kEvent: {
        absl::StatusOr<JobEvent> event = JobEventFromAgentEvent(message.event());
        if (event.ok()) {
          jobs_->OnRobotEvent(robot_id_, *event);
          return absl::OkStatus();
        }
        // Events that are not about jobs (bumper, localization lost) are accepted as is.
        return message.event().type() == v1::AgentEvent::TYPE_UNSPECIFIED ? event.status()
                                                                          : absl::OkStatus();
      }
      case v1::AgentMessage::kHello:
        return absl::InvalidArgumentError("hello: sent twice on one stream");
      case v1::AgentMessage::PAYLOAD_NOT_SET:
        break;
    }
    return absl::InvalidArgumentError("payload: empty agent message");
  }

  /// Starts the next write if none is in flight; finishes the call once ending and drained.
  void PumpWrites() {
    absl::MutexLock lock(&mutex_);
    if (writing_ || finished_) return;
    if (!broken_ && registered_ && outbox_ != nullptr) {
      if (std::optional<v1::ServerMessage> next = outbox_->TryPop()) {
        out_ = std::move(*next);
        writing_ = true;
        StartWrite(&out_);
        return;
      }
    }
    if (ending_) {
      finished_ = true;
      Finish(ToGrpcStatus(end_status_));
    }
  }

  void End(const absl::Status& status) {
    {
      absl::MutexLock lock(&mutex_);
      if (ending_) return;
      ending_ = true;
      end_status_ = status;
      if (!status.ok()) broken_ = true;  // an error ends the call without more writes
    }
    if (outbox_ != nullptr) outbox_->Close();
    PumpWrites();
  }

  FleetRegistry* registry_;
  JobService* jobs_;
  AgentMailbox* mailbox_;
  v1::AgentMessage in_;
  std::string robot_id_;
  uint64_t session_ = 0;
  bool hello_seen_ = false;  ///< touched only by the read chain
  std::shared_ptr<AgentOutbox> outbox_;
  absl::Mutex mutex_;
  v1::ServerMessage out_ ABSL_GUARDED_BY(mutex_);
  bool writing_ ABSL_GUARDED_BY(mutex_) = false;
  bool registered_ ABSL_GUARDED_BY(mutex_) = false;
  bool broken_ ABSL_GUARDED_BY(mutex_) = false;
  bool ending_ ABSL_GUARDED_BY(mutex_) = false;
  bool finished_ ABSL_GUARDED_BY(mutex_) = false;
  absl::Status end_status_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace

grpc::ServerBidiReactor<v1::AgentMessage, v1::ServerMessage>* AgentServiceImpl::Connect(
    grpc::CallbackServerContext*) {
  return new AgentConnection(registry_, jobs_, mailbox_);
}

}  // namespace fleetnav::server
