#include "fleetnav/robot_agent/server_link.hpp"

#include <algorithm>
#include <chrono>

#include "fleetnav/proto/assignment_convert.hpp"
#include "fleetnav/proto/job_convert.hpp"
#include "fleetnav/proto/route_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/proto/zone_convert.hpp"

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
  DropOldTelemetry();
  changed_.SignalAll();
}

void ServerLink::DropOldTelemetry() {
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

std::vector<RobotStop> ServerLink::Stops() {
  absl::MutexLock lock(&mutex_);
  return stops_;
}

std::optional<ToldZones> ServerLink::Zones(const std::string& map_id) {
  absl::MutexLock lock(&mutex_);
  auto it = zones_.find(map_id);
  if (it == zones_.end()) return std::nullopt;
  return it->second;
}

bool ServerLink::HearsServer() {
  absl::MutexLock lock(&mutex_);
  return welcomed_;
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
  changed_.SignalAll();
}

void ServerLink::SetCurrentJob(const std::string& job_id) {
  absl::MutexLock lock(&mutex_);
  current_job_id_ = job_id;
}

void ServerLink::EndTick(const SensorFrame& frame) {
  // Not one of fleetnavd's ticks: what was sent is taken in at its next one.
  if (!params_.lockstep || frame.lockstep_robot_ids.empty()) return;
  absl::MutexLock lock(&mutex_);
  if (closing_ || !session_live_) {
    last_tick_alone_ = frame.tick;
    return;
  }
  v1::TickDone done;
  done.set_tick(frame.tick);
  done.set_sim_time_ns(frame.stamp_ns);
  for (const std::string& id : frame.lockstep_robot_ids) done.add_lockstep_robot_ids(id);
  tick_done_ = std::move(done);
  changed_.SignalAll();  // the writer sends it
  awaited_ack_ = AwaitedAck{session_, frame.tick};
  // Before a hold whoever acts during it must find the server done with the tick; otherwise the
  // server takes it in while the simulator steps, and the next frame waits for that.
  if (frame.holds_after) AwaitAck();
}

void ServerLink::BeginTick() {
  if (!params_.lockstep) return;
  absl::MutexLock lock(&mutex_);
  AwaitAck();
}

void ServerLink::AwaitAck() {
  if (!awaited_ack_) return;
  const AwaitedAck awaited = *awaited_ack_;
  awaited_ack_.reset();
  // No wall-clock timeout: a slow server makes the run slower, never different. A server that
  // goes away ends the session, and with it the wait.
  auto answered = [&]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) {
    return closing_ || session_ != awaited.session || !session_live_ ||
           (acknowledged_tick_ && *acknowledged_tick_ >= awaited.tick);
  };
  while (!answered()) changed_.Wait(&mutex_);
}

void ServerLink::OnServerMessage(const v1::ServerMessage& message) {
  absl::MutexLock lock(&mutex_);
  changed_.SignalAll();  // on the way out, under the lock
  if (!params_.lockstep || message.has_welcome()) {
    ApplyServerMessage(message);
    return;
  }
  if (!message.has_tick_ack()) {
    held_.push_back(message);
    return;
  }
  acknowledged_tick_ = message.tick_ack().tick();
  for (const v1::ServerMessage& held : held_) ApplyServerMessage(held);
  held_.clear();
  while (!unacknowledged_.empty() && unacknowledged_.front().tick &&
         *unacknowledged_.front().tick <= *acknowledged_tick_) {
    unacknowledged_.pop_front();
  }
}

void ServerLink::SessionEnded() {
  for (const v1::ServerMessage& held : held_) ApplyServerMessage(held);
  held_.clear();
  session_live_ = false;
  welcomed_ = false;
  tick_done_.reset();
  acknowledged_tick_.reset();
  for (auto sent = unacknowledged_.rbegin(); sent != unacknowledged_.rend(); ++sent) {
    if (sent->event) events_.push_front(std::move(*sent->event));
    if (sent->telemetry) queue_.push_front(std::move(*sent->telemetry));
  }
  unacknowledged_.clear();
  DropOldTelemetry();
  changed_.SignalAll();
}

std::optional<v1::AgentMessage> ServerLink::NextMessage() {
  v1::AgentMessage message;
  if (!events_.empty()) {  // events first: they change job states
    *message.mutable_event() = ToAgentEvent(events_.front(), 0);
  } else if (!queue_.empty()) {
    *message.mutable_telemetry() = ToProto(queue_.front());
  } else if (tick_done_) {
    *message.mutable_tick_done() = *tick_done_;
  } else {
    return std::nullopt;
  }
  return message;
}

void ServerLink::MessageWritten(const v1::AgentMessage& message) {
  changed_.SignalAll();  // a queue may have drained (Close waits for that)
  Unacknowledged sent;
  if (message.has_event() && !events_.empty()) {
    sent.event = std::move(events_.front());
    events_.pop_front();
  } else if (message.has_telemetry() && !queue_.empty()) {
    sent.telemetry = std::move(queue_.front());
    queue_.pop_front();
    sent_.fetch_add(1);
  } else if (message.has_tick_done()) {
    // The server may have answered before Write returned, and the next tick's TickDone be
    // waiting already: only the one written is done with.
    if (tick_done_ && tick_done_->tick() == message.tick_done().tick()) tick_done_.reset();
    for (Unacknowledged& earlier : unacknowledged_) {
      if (!earlier.tick) earlier.tick = message.tick_done().tick();
    }
    return;
  }
  if (params_.lockstep) unacknowledged_.push_back(std::move(sent));
}

void ServerLink::ApplyServerMessage(const v1::ServerMessage& message) {
  if (message.has_welcome()) welcomed_ = true;
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
  } else if (message.has_stops() || message.has_welcome()) {
    // The whole list in force (a new session's, or a change) replaces the last; one that does
    // not parse is kept in force by standing (a stop of the whole fleet) rather than dropped.
    const auto& wires = message.has_stops() ? message.stops().stops() : message.welcome().stops();
    std::vector<RobotStop> stops;
    for (const v1::RobotStop& wire : wires) {
      absl::StatusOr<RobotStop> stop = FromProto(wire);
      stops.push_back(stop.ok() ? *std::move(stop) : RobotStop{});
    }
    stops_ = std::move(stops);
  } else if (message.has_zones()) {
    // A set that does not parse is not acted on: the zones the job began with stay.
    if (absl::StatusOr<ZoneSet> zones = FromProto(message.zones().zones()); zones.ok()) {
      const std::string map_id = zones->map_id;
      zones_[map_id] = ToldZones{message.zones().version(), *std::move(zones)};
    }
  } else if (message.has_clearance()) {
    // A malformed hold is not acted on: the clearance before it stays.
    if (absl::StatusOr<JobCommand> clearance = FromProto(message.clearance()); clearance.ok()) {
      commands_.push_back(*std::move(clearance));
    }
  }
}

void ServerLink::Close(double timeout_s) {
  {
    absl::MutexLock lock(&mutex_);
    if (closing_ && !thread_.joinable()) return;
    const absl::Time give_up = absl::Now() + absl::Seconds(timeout_s);
    while (!(queue_.empty() && events_.empty())) {
      if (changed_.WaitWithDeadline(&mutex_, give_up)) break;
    }
    closing_ = true;
    changed_.SignalAll();
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
    const absl::Time retry = absl::Now() + absl::Seconds(backoff_s);
    while (!closing_ && !changed_.WaitWithDeadline(&mutex_, retry)) {
    }
    if (closing_) return;
    backoff_s = std::min(backoff_s * 2.0, params_.max_backoff_s);
  }
}

void ServerLink::RunSession() {
  grpc::ClientContext context;
  auto stream = stub_->Connect(&context);
  v1::AgentMessage hello;
  *hello.mutable_hello() = ToProto(identity_);
  hello.mutable_hello()->set_lockstep(params_.lockstep);
  {
    absl::MutexLock lock(&mutex_);
    hello.mutable_hello()->set_resume_job_id(current_job_id_);
    if (params_.lockstep && last_tick_alone_) {
      hello.mutable_hello()->set_lockstep_from_tick(*last_tick_alone_ + 1);
    }
    // Live before the hello goes: a tick that ends from now on is waited for by the server.
    ++session_;
    session_live_ = true;
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
    absl::MutexLock lock(&mutex_);
    server_done.store(true);
    SessionEnded();
  });
  while (ok) {
    std::optional<v1::AgentMessage> message;
    {
      absl::MutexLock lock(&mutex_);
      auto ready = [&]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) {
        return closing_ || server_done.load() || !queue_.empty() || !events_.empty() ||
               tick_done_.has_value();
      };
      while (!ready()) changed_.Wait(&mutex_);
      if (server_done.load()) break;
      message = NextMessage();
      if (!message) break;  // closing with nothing left to send
    }
    ok = stream->Write(*message);
    if (ok) {
      absl::MutexLock lock(&mutex_);
      // In lockstep, a session that ended meanwhile put what it sent back in the queues, before
      // this one, which is then still at the front: sent again with the others.
      if (!params_.lockstep || session_live_) MessageWritten(*message);
    }
  }
  {
    absl::MutexLock lock(&mutex_);
    session_live_ = false;  // a tick ending now waits for no one
    welcomed_ = false;
    changed_.SignalAll();
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
