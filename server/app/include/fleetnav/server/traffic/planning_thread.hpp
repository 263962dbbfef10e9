#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <thread>

#include "absl/synchronization/mutex.h"
#include "fleetnav/server/traffic/pass_timings.hpp"

namespace fleetnav::server {

/// Runs traffic coordination's searches (the lattice searches of route predictions and of ways
/// round robots that stand) on a thread of its own, so that a dispatcher pass only decides and
/// the searches of a pass are taken up by a later one. Tasks run one at a time in the order
/// they are given; each is known by its ticket (1, 2, ...), and a ticket is done once that many
/// tasks have finished. `on_done` is called on the thread after each task (fleetnavd wakes its
/// dispatcher with it). Before Start, and after Stop, Add runs the task at once on the caller's
/// thread, so a caller without the thread (unit tests) sees every result at once. It times each
/// task in the thread's CPU time. Thread-safe.
class PlanningThread {
 public:
  PlanningThread() = default;
  ~PlanningThread() { Stop(); }
  PlanningThread(const PlanningThread&) = delete;
  PlanningThread& operator=(const PlanningThread&) = delete;

  /// Starts the thread (once).
  void Start(std::function<void()> on_done);
  /// Ends the thread after the task it is running; tasks not begun are dropped.
  void Stop();
  /// Queues `task` (or runs it at once, without the thread) and returns its ticket.
  uint64_t Add(std::function<void()> task);
  /// Whether tasks are queued for the thread (Start was called and Stop was not).
  bool threaded();
  /// Whether the task of `ticket` has finished (what it wrote is then safe to read).
  bool Done(uint64_t ticket);
  /// Blocks until every task given so far has finished (a simulated run's lockstep, so that
  /// each result is taken up by the same pass in every run).
  void WaitForAll();
  /// CPU time of the tasks run on the thread. Read after Stop.
  PassFigures task_cpu() const { return task_cpu_.Figures(); }

 private:
  void Run();

  absl::Mutex mutex_;
  std::deque<std::function<void()>> queue_ ABSL_GUARDED_BY(mutex_);
  uint64_t given_ ABSL_GUARDED_BY(mutex_) = 0;
  uint64_t finished_ ABSL_GUARDED_BY(mutex_) = 0;
  bool running_ ABSL_GUARDED_BY(mutex_) = false;
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;
  std::function<void()> on_done_;
  PassTimings task_cpu_;  ///< written by the thread only
  std::thread thread_;
};

}  // namespace fleetnav::server
