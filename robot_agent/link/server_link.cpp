#include "fleetnav/robot_agent/server_link.hpp"

#include <algorithm>
#include <chrono>

#include "fleetnav/proto/telemetry_convert.hpp"

namespace fleetnav::agent {

ServerLink::ServerLink(std::shared_ptr<grpc::Channel> channel, RobotIdentity identity,
                       ServerLinkParams params)
    : stub_(v1::AgentService::NewStub(channel)),
      identity_(std::move(identity)),
      params_(params),
      thread_([this] { RunLoop(); }) {}

ServerLink::~ServerLink() { Close(0.0); }

void ServerLink::Publish(const Telemetry& telemetry) {
  absl::MutexLock lock(&mutex_);
  if (closing_) return;
  queue_.push_back(telemetry);
  while (queue_.size() > params_.max_queued) {
    queue_.pop_front();
    dropped_.fetch_add(1);
  }
}

void ServerLink::Close(double timeout_s) {
  {
    absl::MutexLock lock(&mutex_);
    if (closing_ && !thread_.joinable()) return;
    auto drained = [this]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) { return queue_.empty(); };
    mutex_.AwaitWithTimeout(absl::Condition(&drained), absl::Seconds(timeout_s));
    closing_ = true;
  }
  if (thread_.joinable()) thread_.join();
}

void ServerLink::RunLoop() {
  double backoff_s = params_.initial_backoff_s;
  while (true) {
    {
      absl::MutexLock lock(&mutex_);
      if (closing_) return;
    }
    const uint64_t sent_before = sent_.load();
    RunSession();
    if (sent_.load() > sent_before) backoff_s = params_.initial_backoff_s;
    absl::MutexLock lock(&mutex_);
    auto closing = [this]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) { return closing_; };
    if (mutex_.AwaitWithTimeout(absl::Condition(&closing), absl::Seconds(backoff_s))) return;
    backoff_s = std::min(backoff_s * 2.0, params_.max_backoff_s);
  }
}

void ServerLink::RunSession() {
  grpc::ClientContext context;
  auto stream = stub_->Connect(&context);
  v1::AgentMessage hello;
  *hello.mutable_hello() = ToProto(identity_);
  bool ok = stream->Write(hello);
  connections_.fetch_add(ok ? 1 : 0);

  // Server messages (welcome, later assignments and commands) are read on a second thread.
  std::atomic<bool> server_done{false};
  std::thread reader([&stream, &server_done] {
    v1::ServerMessage message;
    while (stream->Read(&message)) {
    }
    server_done.store(true);
  });
  while (ok) {
    Telemetry next;
    {
      absl::MutexLock lock(&mutex_);
      auto ready = [this]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) {
        return closing_ || !queue_.empty();
      };
      mutex_.Await(absl::Condition(&ready));
      if (queue_.empty()) break;  // closing with nothing left to send
      next = queue_.front();
    }
    v1::AgentMessage message;
    *message.mutable_telemetry() = ToProto(next);
    ok = stream->Write(message);
    if (ok) {
      absl::MutexLock lock(&mutex_);
      if (!queue_.empty()) queue_.pop_front();
      sent_.fetch_add(1);
    }
  }
  // Half-close and let the server read everything it has; cancel only if it does not finish.
  stream->WritesDone();
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (!server_done.load() && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (!server_done.load()) context.TryCancel();
  reader.join();
  (void)stream->Finish();
}

}  // namespace fleetnav::agent
