#include "fleetnav/server/rpc/watch_hub.hpp"

#include <grpcpp/server_context.h>

#include <chrono>
#include <cmath>
#include <deque>
#include <limits>

#include "absl/strings/str_cat.h"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/proto/job_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"

namespace fleetnav::server {
namespace {

using SteadyTime = std::chrono::steady_clock::time_point;

int64_t SteadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

/// One watch stream's gRPC half, driven only by the hub's thread: accepted, then writes one
/// message at a time, then Finish; deleted once gRPC has returned every tag it was given (the
/// write, the finish and the done notification).
class WatchStream {
 public:
  explicit WatchStream(WatchHub* hub) : hub_(hub) {}
  virtual ~WatchStream() = default;

  static void Proceed(void* tag, bool ok) {
    const auto bits = reinterpret_cast<uintptr_t>(tag);
    auto* stream = reinterpret_cast<WatchStream*>(bits & ~uintptr_t{3});
    stream->Handle(static_cast<WatchHub::Op>(bits & 3), ok);
  }

 protected:
  void* Tag(WatchHub::Op op) {
    return reinterpret_cast<void*>(reinterpret_cast<uintptr_t>(this) | static_cast<uintptr_t>(op));
  }
  /// Validates the request and registers with the hub, or ends the stream with an error.
  virtual void Accepted() = 0;
  /// The previous write completed; the stream may write again.
  virtual void Written() = 0;
  /// Called once, before deletion.
  virtual void Unregister() = 0;
  virtual void StartFinish(const grpc::Status& status) = 0;

  bool busy() const { return writing_ || finish_called_; }
  /// Finishes now, or after the write in flight.
  void End(const grpc::Status& status) {
    if (finish_called_) return;
    end_status_ = status;
    end_requested_ = true;
    if (writing_) return;
    finish_called_ = true;
    StartFinish(status);
  }
  /// The context must learn of the done tag before the call is requested.
  void NotifyWhenDone(grpc::ServerContext* context) {
    context->AsyncNotifyWhenDone(Tag(WatchHub::Op::kDone));
  }

  WatchHub* hub_;
  bool writing_ = false;

 private:
  void Handle(WatchHub::Op op, bool ok) {
    switch (op) {
      case WatchHub::Op::kAccepted:
        if (!ok) {  // the server is shutting down: the call never started, no other tag comes
          Unregister();
          delete this;
          return;
        }
        accepted_ = true;
        Accepted();
        break;
      case WatchHub::Op::kWrite:
        writing_ = false;
        if (!ok) {
          End(grpc::Status::OK);  // the client is gone
        } else if (end_requested_) {
          End(end_status_);
        } else if (!done_) {
          Written();
        }
        break;
      case WatchHub::Op::kFinish:
        finish_done_ = true;
        break;
      case WatchHub::Op::kDone:
        done_ = true;
        break;
    }
    // A call that is over (cancelled, deadline, client gone) is finished once no write is in
    // flight, whichever tag came last.
    if (done_ && !finish_called_ && !writing_) End(grpc::Status::OK);
    if (accepted_ && done_ && finish_done_ && !writing_) {
      Unregister();
      delete this;
    }
  }

  bool accepted_ = false;
  bool finish_called_ = false;
  bool finish_done_ = false;
  bool done_ = false;
  bool end_requested_ = false;
  grpc::Status end_status_;
};

/// The typed half of a watch stream: its context, request, writer and the message in flight.
template <typename Request, typename Message>
class TypedWatchStream : public WatchStream {
 protected:
  explicit TypedWatchStream(WatchHub* hub) : WatchStream(hub), writer_(&context_) {
    NotifyWhenDone(&context_);
  }
  /// Writes message_, which stays untouched until Written().
  void WriteMessage() {
    writing_ = true;
    writer_.Write(message_, Tag(WatchHub::Op::kWrite));
  }
  void StartFinish(const grpc::Status& status) override {
    writer_.Finish(status, Tag(WatchHub::Op::kFinish));
  }

  grpc::ServerContext context_;
  Request request_;
  grpc::ServerAsyncWriter<Message> writer_;
  Message message_;
};

/// A WatchFleet stream: a snapshot, then the robots that changed (and the ids removed) at most
/// at its rate.
class FleetWatcher final : public TypedWatchStream<v1::WatchFleetRequest, v1::FleetUpdate> {
 public:
  explicit FleetWatcher(WatchHub* hub) : TypedWatchStream(hub) {
    hub_->service_->RequestWatchFleet(&context_, &request_, &writer_, hub_->cq_.get(),
                                      hub_->cq_.get(), Tag(WatchHub::Op::kAccepted));
  }

  /// Writes what changed if due; returns when it next wants to be asked (max(): only after a
  /// change).
  SteadyTime Serve(uint64_t revision, uint64_t removals, SteadyTime now) {
    if (busy()) return SteadyTime::max();  // Written() asks again
    const bool news = first_ || revision > seen_revision_ || removals != seen_removals_;
    if (!news) return SteadyTime::max();
    if (now < next_due_) return next_due_;
    v1::FleetUpdate& update = message_;
    update.Clear();
    update.set_snapshot(first_);
    uint64_t latest = 0;
    for (const RobotRecord& record :
         hub_->registry_->ChangedSince(first_ ? 0 : seen_revision_, &latest)) {
      known_.insert(record.identity.robot_id);
      *update.add_robots() = ToProto(record);
    }
    seen_revision_ = latest;
    if (removals != seen_removals_) {
      std::set<std::string> present;
      for (const RobotRecord& record : hub_->registry_->Snapshot()) {
        present.insert(record.identity.robot_id);
      }
      for (auto it = known_.begin(); it != known_.end();) {
        if (present.count(*it) > 0) {
          ++it;
          continue;
        }
        update.add_removed_robot_ids(*it);
        it = known_.erase(it);
      }
      seen_removals_ = removals;
    }
    if (!first_ && update.robots_size() == 0 && update.removed_robot_ids_size() == 0) {
      return SteadyTime::max();
    }
    first_ = false;
    update.set_server_time_ns(SteadyNowNs());
    next_due_ = now + period_;
    WriteMessage();
    return SteadyTime::max();
  }

 private:
  void Accepted() override {
    hub_->AcceptFleetWatcher();
    const double rate_hz = request_.rate_hz() == 0.0 ? 10.0 : request_.rate_hz();
    if (!std::isfinite(rate_hz) || rate_hz < 0.0 || rate_hz > 100.0) {
      End(ToGrpcStatus(absl::InvalidArgumentError(
          absl::StrCat("rate_hz: must be in (0, 100], got ", request_.rate_hz()))));
      return;
    }
    period_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(1.0 / rate_hz));
    hub_->fleet_.insert(this);
    hub_->fleet_watchers_.fetch_add(1);
    registered_ = true;
    hub_->fleet_dirty_.store(true);
  }
  void Written() override { hub_->fleet_dirty_.store(true); }
  void Unregister() override {
    if (registered_) {
      hub_->fleet_.erase(this);
      hub_->fleet_watchers_.fetch_sub(1);
    }
    hub_->Gone();
  }

  std::chrono::steady_clock::duration period_{};
  SteadyTime next_due_{};
  bool first_ = true;
  bool registered_ = false;
  uint64_t seen_revision_ = 0;
  uint64_t seen_removals_ = 0;
  std::set<std::string> known_;  ///< robots sent and not yet reported removed
};

/// A WatchJob stream: the job's events in order from the first, ending after the one that ends
/// the job.
class JobWatcher final : public TypedWatchStream<v1::WatchJobRequest, v1::JobEvent> {
 public:
  explicit JobWatcher(WatchHub* hub) : TypedWatchStream(hub) {
    hub_->service_->RequestWatchJob(&context_, &request_, &writer_, hub_->cq_.get(),
                                    hub_->cq_.get(), Tag(WatchHub::Op::kAccepted));
  }

  const std::string& job_id() const { return request_.job_id(); }

  /// Writes the next stored event this watcher has not sent, if it can write now.
  void Serve() {
    if (busy()) return;  // Written() asks again
    if (pending_.empty()) {
      absl::StatusOr<std::vector<JobEvent>> events = hub_->jobs_->Events(job_id(), after_);
      if (!events.ok()) {
        End(ToGrpcStatus(events.status()));
        return;
      }
      pending_.assign(events->begin(), events->end());
    }
    if (pending_.empty()) return;
    const JobEvent event = pending_.front();
    pending_.pop_front();
    after_ = event.sequence;
    ended_ = IsTerminal(event.state);
    message_ = fleetnav::ToProto(event);
    WriteMessage();
  }

 private:
  void Accepted() override {
    hub_->AcceptJobWatcher();
    absl::StatusOr<Job> job = hub_->jobs_->Get(job_id());
    if (!job.ok()) {
      End(ToGrpcStatus(job.status()));
      return;
    }
    hub_->jobs_by_id_.emplace(job_id(), this);
    hub_->job_watchers_.fetch_add(1);
    registered_ = true;
    Serve();
  }
  void Written() override {
    if (ended_) {
      End(grpc::Status::OK);  // the job is over: the stream ends with it
      return;
    }
    Serve();  // the next pending event, or any stored while this one was written
  }
  void Unregister() override {
    if (registered_) {
      auto [begin, end] = hub_->jobs_by_id_.equal_range(job_id());
      for (auto it = begin; it != end; ++it) {
        if (it->second == this) {
          hub_->jobs_by_id_.erase(it);
          break;
        }
      }
      hub_->job_watchers_.fetch_sub(1);
    }
    hub_->Gone();
  }

  std::deque<JobEvent> pending_;
  int64_t after_ = 0;
  bool ended_ = false;
  bool registered_ = false;
};

WatchHub::WatchHub(FleetServiceBase* service, FleetRegistry* registry, JobService* jobs)
    : service_(service), registry_(registry), jobs_(jobs) {}

WatchHub::~WatchHub() { Shutdown(); }

void WatchHub::Register(grpc::ServerBuilder* builder) { cq_ = builder->AddCompletionQueue(); }

void WatchHub::Start() {
  AcceptFleetWatcher();
  AcceptJobWatcher();
  thread_ = std::thread([this] { Run(); });
}

bool WatchHub::Reserve() {
  absl::MutexLock lock(&signal_mutex_);
  if (stopping_) return false;
  ++live_;
  return true;
}

void WatchHub::AcceptFleetWatcher() {
  if (Reserve()) new FleetWatcher(this);
}

void WatchHub::AcceptJobWatcher() {
  if (Reserve()) new JobWatcher(this);
}

void WatchHub::Gone() {
  absl::MutexLock lock(&signal_mutex_);
  --live_;
}

void WatchHub::Wake() {
  if (wake_pending_.exchange(true)) return;
  absl::MutexLock lock(&signal_mutex_);
  if (stopping_) return;
  wake_alarm_.Set(cq_.get(), gpr_now(GPR_CLOCK_MONOTONIC), &wake_alarm_);
}

void WatchHub::OnFleetChanged() {
  if (fleet_watchers_.load(std::memory_order_relaxed) == 0) return;
  if (fleet_dirty_.exchange(true)) return;  // the hub has not looked since the last change
  Wake();
}

void WatchHub::OnJobChanged(const std::string& job_id) {
  if (job_watchers_.load(std::memory_order_relaxed) == 0) return;
  {
    absl::MutexLock lock(&signal_mutex_);
    dirty_jobs_.insert(job_id);
  }
  Wake();
}

SteadyTime WatchHub::ServeFleetWatchers() {
  const uint64_t revision = registry_->revision();
  const uint64_t removals = registry_->removals();
  const SteadyTime now = std::chrono::steady_clock::now();
  SteadyTime next = SteadyTime::max();
  // Serving never removes a watcher: that happens only when a tag of it comes back.
  for (FleetWatcher* watcher : fleet_) {
    next = std::min(next, watcher->Serve(revision, removals, now));
  }
  return next;
}

void WatchHub::ServeJobWatchers(const std::set<std::string>& job_ids) {
  for (const std::string& job_id : job_ids) {
    auto [begin, end] = jobs_by_id_.equal_range(job_id);
    for (auto it = begin; it != end; ++it) it->second->Serve();
  }
}

void WatchHub::Run() {
  SteadyTime next_fleet = SteadyTime::max();
  while (true) {
    void* tag = nullptr;
    bool ok = false;
    // Sleep until an event, or until a fleet watcher with news becomes due.
    const auto deadline = next_fleet == SteadyTime::max()
                              ? std::chrono::system_clock::now() + std::chrono::hours(1)
                              : std::chrono::system_clock::now() +
                                    std::chrono::duration_cast<std::chrono::system_clock::duration>(
                                        next_fleet - std::chrono::steady_clock::now());
    const grpc::CompletionQueue::NextStatus status = cq_->AsyncNext(&tag, &ok, deadline);
    if (status == grpc::CompletionQueue::SHUTDOWN) return;
    if (status == grpc::CompletionQueue::GOT_EVENT) {
      if (tag == &wake_alarm_) {
        wake_pending_.store(false);
      } else {
        WatchStream::Proceed(tag, ok);
      }
    }
    std::set<std::string> jobs;
    {
      absl::MutexLock lock(&signal_mutex_);
      jobs.swap(dirty_jobs_);
    }
    if (!jobs.empty()) ServeJobWatchers(jobs);
    const bool fleet_due =
        next_fleet != SteadyTime::max() && std::chrono::steady_clock::now() >= next_fleet;
    if (fleet_dirty_.exchange(false) || fleet_due) next_fleet = ServeFleetWatchers();
  }
}

void WatchHub::Shutdown() {
  if (shut_down_ || cq_ == nullptr) return;
  shut_down_ = true;
  {
    absl::MutexLock lock(&signal_mutex_);
    stopping_ = true;
  }
  if (thread_.joinable()) {
    // The server's Shutdown() ended every stream and returned every awaited call; once their
    // tags are handled no operation is pending, and the queue may shut down.
    absl::MutexLock lock(&signal_mutex_);
    auto none = [this]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(signal_mutex_) { return live_ == 0; };
    signal_mutex_.Await(absl::Condition(&none));
  }
  wake_alarm_.Cancel();
  cq_->Shutdown();
  if (thread_.joinable()) {
    thread_.join();
  } else {
    void* tag = nullptr;
    bool ok = false;
    while (cq_->Next(&tag, &ok)) {
      if (tag != &wake_alarm_) WatchStream::Proceed(tag, ok);
    }
  }
}

}  // namespace fleetnav::server
