#include "fleetnav/server/rpc/agent_service.hpp"

#include <chrono>

#include "absl/strings/str_cat.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/proto/job_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/proto/zone_convert.hpp"

namespace fleetnav::server {

/// One robot's stream, or the wait for the next one on a completion queue. Completions of its
/// queue arrive on one thread: reads run one after another (each completed read starts the
/// next); writes come from the outbox, one at a time, started from any thread; Finish() is
/// called once, after the last write, and its completion deletes the connection.
class AgentConnection final {
 public:
  enum class Op : uintptr_t { kAccepted = 0, kRead = 1, kWrite = 2, kFinished = 3 };

  AgentConnection(AgentServiceImpl* service, grpc::ServerCompletionQueue* cq)
      : service_(service),
        sessions_(service->sessions_),
        mailbox_(service->mailbox_),
        cq_(cq),
        stream_(&context_) {
    service_->service_.RequestConnect(&context_, &stream_, cq_, cq_, Tag(Op::kAccepted));
  }

  static void Proceed(void* tag, bool ok) {
    const auto bits = reinterpret_cast<uintptr_t>(tag);
    auto* connection = reinterpret_cast<AgentConnection*>(bits & ~uintptr_t{3});
    switch (static_cast<Op>(bits & 3)) {
      case Op::kAccepted:
        connection->OnAccepted(ok);
        break;
      case Op::kRead:
        connection->OnReadDone(ok);
        break;
      case Op::kWrite:
        connection->OnWriteDone(ok);
        break;
      case Op::kFinished:
        connection->OnFinished();
        break;
    }
  }

 private:
  void* Tag(Op op) {
    return reinterpret_cast<void*>(reinterpret_cast<uintptr_t>(this) | static_cast<uintptr_t>(op));
  }

  void OnAccepted(bool ok) {
    if (!ok) {  // the server is shutting down: no call came
      AgentServiceImpl* service = service_;
      delete this;
      service->ConnectionGone();
      return;
    }
    service_->Accept(cq_);  // the next robot's call
    {
      absl::MutexLock lock(&mutex_);
      writing_ = true;
      stream_.SendInitialMetadata(Tag(Op::kWrite));
    }
    StartRead();
  }

  void StartRead() {
    read_pending_ = true;
    stream_.Read(&in_, Tag(Op::kRead));
  }

  void OnReadDone(bool ok) {
    read_pending_ = false;
    if (!ok) {  // the agent hung up (or the call was cancelled)
      End(absl::OkStatus());
      return;
    }
    absl::Status status;
    if (!hello_seen_) {
      status = Hello(in_);
    } else if (member_ && in_.has_tick_done()) {
      service_->barrier_->EndTick(*member_, in_.tick_done());
    } else if (!member_ || !service_->barrier_->Hold(*member_, in_)) {
      status = Handle(in_);
    }
    if (!status.ok()) {
      End(status);
      return;
    }
    StartRead();
  }

  void OnWriteDone(bool ok) {
    {
      absl::MutexLock lock(&mutex_);
      writing_ = false;
      if (!ok) broken_ = true;
      // An assignment of a long route is hundreds of kB: not kept once written (Clear() would
      // keep its capacity).
      if (out_.has_assignment()) out_ = v1::ServerMessage();
    }
    PumpWrites();
  }

  void OnFinished() {
    // What the robot sent of its last tick is taken in before it is disconnected.
    if (member_) service_->barrier_->Leave(*member_);
    if (outbox_ != nullptr) mailbox_->Close(robot_id_, outbox_);
    if (hello_seen_) sessions_->Close(robot_id_, session_);
    AgentServiceImpl* service = service_;
    delete this;
    service->ConnectionGone();
  }

  absl::Status Hello(const v1::AgentMessage& message) {
    if (message.payload_case() != v1::AgentMessage::kHello) {
      return absl::InvalidArgumentError("the first message on an agent stream must be `hello`");
    }
    absl::StatusOr<RobotIdentity> identity = FromProto(message.hello());
    if (!identity.ok()) return identity.status();
    // Checked before anything of it is kept: the registry holds a hello for good.
    if (absl::Status limited = sessions_->CheckHello(*identity); !limited.ok()) return limited;
    if (service_->gate_ != nullptr) {
      absl::Status claim = service_->gate_->CheckRobotClaim(context_, identity->robot_id);
      if (!claim.ok()) return claim;
    }
    robot_id_ = identity->robot_id;
    hello_seen_ = true;
    v1::ServerMessage welcome;
    welcome.mutable_welcome()->set_server_time_ns(
        std::chrono::duration_cast<std::chrono::nanoseconds>(
            std::chrono::steady_clock::now().time_since_epoch())
            .count());
    welcome.mutable_welcome()->set_telemetry_rate_hz(10.0);
    // The stops it must keep to, before anything else it hears.
    for (const RobotStop& stop : sessions_->StopsInForce()) {
      *welcome.mutable_welcome()->add_stops() = ToProto(stop);
    }
    // Settle the jobs this robot held before it shows as online, so that the dispatcher cannot
    // hand it new work in between; its outbox is open (welcome first) before then too.
    outbox_ = mailbox_->Open(robot_id_, [this] { PumpWrites(); });
    outbox_->Push(std::move(welcome));
    if (message.hello().lockstep() && service_->barrier_ != nullptr) {
      member_ = service_->barrier_->Join(
          robot_id_, message.hello().lockstep_from_tick(),
          [this](const v1::AgentMessage& held) {
            if (absl::Status taken = Handle(held); !taken.ok()) End(taken);
          },
          [outbox = outbox_](uint64_t tick) {
            v1::ServerMessage ack;
            ack.mutable_tick_ack()->set_tick(tick);
            outbox->Push(std::move(ack));
          });
    }
    session_ = sessions_->Open(*identity, message.hello().resume_job_id());
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
        absl::Status recorded = sessions_->RecordTelemetry(robot_id_, session_, *telemetry);
        if (recorded.ok()) service_->telemetry_messages_.fetch_add(1, std::memory_order_relaxed);
        return recorded;
      }
      case v1::AgentMessage::kEvent: {
        absl::StatusOr<JobEvent> event = JobEventFromAgentEvent(message.event());
        if (event.ok()) return sessions_->RecordJobEvent(robot_id_, session_, *event);
        if (absl::Status s = sessions_->CheckSession(robot_id_, session_); !s.ok()) return s;
        // Events that are not about jobs (bumper, localization lost) are accepted as is.
        return message.event().type() == v1::AgentEvent::TYPE_UNSPECIFIED ? event.status()
                                                                          : absl::OkStatus();
      }
      case v1::AgentMessage::kHello:
        return absl::InvalidArgumentError("hello: sent twice on one stream");
      case v1::AgentMessage::kTickDone:
        return absl::OkStatus();  // a stream not in lockstep (no barrier here): nothing to wait for
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
        stream_.Write(out_, Tag(Op::kWrite));
        return;
      }
    }
    if (ending_) {
      finished_ = true;
      stream_.Finish(ToGrpcStatus(end_status_), Tag(Op::kFinished));
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

  AgentServiceImpl* service_;
  RobotSessions* sessions_;
  AgentMailbox* mailbox_;
  grpc::ServerCompletionQueue* cq_;
  grpc::ServerContext context_;
  grpc::ServerAsyncReaderWriter<v1::ServerMessage, v1::AgentMessage> stream_;
  v1::AgentMessage in_;  ///< touched only by the read chain, as are the next four
  bool read_pending_ = false;
  std::string robot_id_;
  uint64_t session_ = 0;
  bool hello_seen_ = false;
  std::optional<uint64_t> member_;  ///< the key in the tick barrier, for a lockstep stream
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

AgentServiceImpl::AgentServiceImpl(RobotSessions* sessions, AgentMailbox* mailbox, int threads,
                                   AccessGate* gate, TickBarrier* barrier)
    : sessions_(sessions),
      mailbox_(mailbox),
      gate_(gate),
      barrier_(barrier),
      thread_count_(std::max(1, threads)) {}

AgentServiceImpl::~AgentServiceImpl() { Shutdown(); }

void AgentServiceImpl::Register(grpc::ServerBuilder* builder) {
  builder->RegisterService(&service_);
  for (int i = 0; i < thread_count_; ++i) cqs_.push_back(builder->AddCompletionQueue());
}

void AgentServiceImpl::Start() {
  // A few calls awaited per queue, so that a burst of robots connecting is taken at once.
  constexpr int kAwaitedPerQueue = 4;
  for (auto& cq : cqs_) {
    for (int i = 0; i < kAwaitedPerQueue; ++i) Accept(cq.get());
    threads_.emplace_back([this, cq = cq.get()] { Serve(cq); });
  }
}

void AgentServiceImpl::Accept(grpc::ServerCompletionQueue* cq) {
  if (stopping_.load()) return;
  {
    absl::MutexLock lock(&live_mutex_);
    ++live_connections_;
  }
  new AgentConnection(this, cq);
}

void AgentServiceImpl::ConnectionGone() {
  absl::MutexLock lock(&live_mutex_);
  --live_connections_;
}

void AgentServiceImpl::Serve(grpc::ServerCompletionQueue* cq) {
  void* tag = nullptr;
  bool ok = false;
  while (cq->Next(&tag, &ok)) AgentConnection::Proceed(tag, ok);
}

void AgentServiceImpl::Shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  stopping_.store(true);
  if (!threads_.empty()) {
    // The server's Shutdown() ended every call and returned every awaited one; once their
    // completions are handled no operation is pending, and the queues may shut down.
    absl::MutexLock lock(&live_mutex_);
    auto none = [this]()
                    ABSL_EXCLUSIVE_LOCKS_REQUIRED(live_mutex_) { return live_connections_ == 0; };
    live_mutex_.Await(absl::Condition(&none));
  }
  for (auto& cq : cqs_) cq->Shutdown();
  for (std::thread& thread : threads_) thread.join();
  for (auto& cq : cqs_) {  // queues never served (the server did not start) still drain
    void* tag = nullptr;
    bool ok = false;
    while (cq->Next(&tag, &ok)) AgentConnection::Proceed(tag, ok);
  }
}

}  // namespace fleetnav::server
