#include "fleetnav/robot_agent/server_link.hpp"

#include <algorithm>
#include <chrono>

#include "fleetnav/proto/assignment_convert.hpp"
#include "fleetnav/proto/job_convert.hpp"
#include "fleetnav/proto/route_convert.hpp"
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

std::optional<JobAssignment> ServerLink::TakeAssignment() {
  absl::MutexLock lock(&mutex_);
  if (assignments_.empty()) return std::nullopt;
  JobAssignment next = std::move(assignments_.front());
  assignments_.pop_front();
  return next;
}

std::vector<JobCommand> ServerLink::TakeCommands() {
  absl::MutexLock lock(&mutex_);
  std::vector<JobCommand> out;
  out.swap(commands_);
  return out;
}

void ServerLink::ReportEvent(const JobEvent& event) {
  absl::MutexLock lock(&mutex_);
  events_.push_back(event);
}

void ServerLink::SetCurrentJob(const std::string& job_id) {
  absl::MutexLock lock(&mutex_);
  current_job_id_ = job_id;
}

void ServerLink::OnServerMessage(const v1::ServerMessage& message) {
  absl::MutexLock lock(&mutex_);
  if (message.has_assignment()) {
    absl::StatusOr<JobAssignment> assignment = FromProto(message.assignment());
    if (assignment.ok()) {
      assignments_.push_back(*std::move(assignment));
    } else {
      // The job cannot run here: say so, so the server fails it rather than waiting.
      JobEvent failed;
      failed.job_id = message.assignment().job().job_id();
      failed.type = JobEventType::kFailed;
      failed.reason = std::string(assignment.status().message());
      events_.push_back(failed);
    }
  } else if (message.has_command()) {
    // An unknown command type (a newer server) is not acted on.
    if (absl::StatusOr<JobCommand> command = FromProto(message.command()); command.ok()) {
      commands_.push_back(*std::move(command));
    }
  } else if (message.has_clearance()) {
    commands_.push_back(FromProto(message.clearance()));
  }
}

void ServerLink::Close(double timeout_s) {
  {
    absl::MutexLock lock(&mutex_);
    if (closing_ && !thread_.joinable()) return;
    auto drained = [this]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) {
      return queue_.empty() && events_.empty();
    };
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
  {
    absl::MutexLock lock(&mutex_);
    hello.mutable_hello()->set_resume_job_id(current_job_id_);
    // A new session (perhaps a restarted server) clears afresh: until it says otherwise the
    // robot finishes the action it is in and stands.
    if (!current_job_id_.empty()) {
      commands_.push_back(JobCommand{JobCommandType::kClearance, current_job_id_, "", -1});
    }
  }
  bool ok = stream->Write(hello);
  connections_.fetch_add(ok ? 1 : 0);

  // Server messages (welcome, later assignments and commands) are read on a second thread.
  std::atomic<bool> server_done{false};
  std::thread reader([this, &stream, &server_done] {
    v1::ServerMessage message;
    while (stream->Read(&message)) OnServerMessage(message);
    server_done.store(true);
  });
  while (ok) {
    v1::AgentMessage message;
    bool is_event = false;
    {
      absl::MutexLock lock(&mutex_);
      auto ready = [this]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) {
        return closing_ || !queue_.empty() || !events_.empty();
      };
      mutex_.Await(absl::Condition(&ready));
      if (!events_.empty()) {  // events first: they change job states
        *message.mutable_event() = ToAgentEvent(events_.front(), 0);
        is_event = true;
      } else if (!queue_.empty()) {
        *message.mutable_telemetry() = ToProto(queue_.front());
      } else {
        break;  // closing with nothing left to send
      }
    }
    ok = stream->Write(message);
    if (ok) {
      absl::MutexLock lock(&mutex_);
      if (is_event && !events_.empty()) {
        events_.pop_front();
      } else if (!is_event && !queue_.empty()) {
        queue_.pop_front();
        sent_.fetch_add(1);
      }
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
