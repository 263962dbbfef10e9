#include "fleetnav/server/traffic/planning_thread.hpp"

#include <utility>

namespace fleetnav::server {

void PlanningThread::Start(std::function<void()> on_done) {
  {
    absl::MutexLock lock(&mutex_);
    if (running_ || stopping_) return;
    running_ = true;
  }
  on_done_ = std::move(on_done);
  thread_ = std::thread([this] { Run(); });
}

void PlanningThread::Stop() {
  {
    absl::MutexLock lock(&mutex_);
    stopping_ = true;
    // Tasks not begun are dropped; their tickets count as finished, so nobody waits for them.
    finished_ += queue_.size();
    queue_.clear();
  }
  if (thread_.joinable()) thread_.join();
  absl::MutexLock lock(&mutex_);
  running_ = false;
}

uint64_t PlanningThread::Add(std::function<void()> task) {
  uint64_t ticket = 0;
  {
    absl::MutexLock lock(&mutex_);
    ticket = ++given_;
    if (running_ && !stopping_) {
      queue_.push_back(std::move(task));
      return ticket;
    }
  }
  task();
  absl::MutexLock lock(&mutex_);
  ++finished_;
  return ticket;
}

bool PlanningThread::threaded() {
  absl::MutexLock lock(&mutex_);
  return running_ && !stopping_;
}

bool PlanningThread::Done(uint64_t ticket) {
  absl::MutexLock lock(&mutex_);
  return finished_ >= ticket;
}

void PlanningThread::WaitForAll() {
  absl::MutexLock lock(&mutex_);
  mutex_.Await(absl::Condition(
      +[](PlanningThread* self)
           ABSL_EXCLUSIVE_LOCKS_REQUIRED(self->mutex_) { return self->finished_ >= self->given_; },
      this));
}

void PlanningThread::Run() {
  while (true) {
    std::function<void()> task;
    {
      absl::MutexLock lock(&mutex_);
      mutex_.Await(absl::Condition(
          +[](PlanningThread* self) ABSL_EXCLUSIVE_LOCKS_REQUIRED(self->mutex_) {
            return self->stopping_ || !self->queue_.empty();
          },
          this));
      if (stopping_) return;
      task = std::move(queue_.front());
      queue_.pop_front();
    }
    const double start_cpu_ms = ThreadCpuMs();
    task();
    task_cpu_.Add(ThreadCpuMs() - start_cpu_ms);
    {
      absl::MutexLock lock(&mutex_);
      ++finished_;
    }
    if (on_done_) on_done_();
  }
}

}  // namespace fleetnav::server
