#pragma once

#include <grpcpp/alarm.h>
#include <grpcpp/server_builder.h>

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <thread>

#include "absl/synchronization/mutex.h"
#include "fleetnav/server/jobs/job_service.hpp"
#include "fleetnav/server/robots/fleet_registry.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"

namespace fleetnav::server {

/// FleetService with its two watch streams on gRPC's async API; every other method is served
/// synchronously by FleetServiceImpl.
using FleetServiceBase = v1::FleetService::WithAsyncMethod_WatchFleet<
    v1::FleetService::WithAsyncMethod_WatchJob<v1::FleetService::Service>>;

class FleetWatcher;
class JobWatcher;
class WatchStream;

/// Serves every WatchFleet and WatchJob stream from one thread and one completion queue: no
/// thread per stream, and no polling. The thread sleeps until a change is signalled (the
/// registry's change listener, the job repository's) or a watcher's pacing time comes, then
/// writes to each affected watcher what changed since its last message. A watcher whose previous
/// write has not completed is skipped and gets the latest state once it has, so a slow client
/// costs one message of memory and holds up nobody; an idle watcher costs nothing.
/// OnFleetChanged/OnJobChanged are cheap and safe from any thread, under any lock.
class WatchHub {
 public:
  WatchHub(FleetServiceBase* service, FleetRegistry* registry, JobService* jobs);
  ~WatchHub();
  WatchHub(const WatchHub&) = delete;
  WatchHub& operator=(const WatchHub&) = delete;

  /// Adds the hub's completion queue to `builder`.
  void Register(grpc::ServerBuilder* builder);
  /// Starts accepting streams; call once, after the server was built.
  void Start();
  /// Call after the server's Shutdown() (which ends the open streams): waits for their ends,
  /// then stops the thread. Idempotent.
  void Shutdown();

  void OnFleetChanged();
  void OnJobChanged(const std::string& job_id);

  /// What a completion-queue tag of a watch stream stands for (its two low bits).
  enum class Op : uintptr_t { kAccepted = 0, kWrite = 1, kFinish = 2, kDone = 3 };

 private:
  friend class FleetWatcher;
  friend class JobWatcher;
  friend class WatchStream;

  void Run();
  /// Asks the thread to look at what changed (an alarm due now on its queue).
  void Wake();
  void AcceptFleetWatcher();
  void AcceptJobWatcher();
  /// Writes to every fleet watcher that is due and has something new; returns the earliest
  /// time a watcher with news becomes due (max() when none waits).
  std::chrono::steady_clock::time_point ServeFleetWatchers();
  void ServeJobWatchers(const std::set<std::string>& job_ids);
  /// Counts a stream (or an awaited call) as live, unless the hub is stopping.
  bool Reserve();
  /// A stream (or an awaited call) has been deleted.
  void Gone();

  FleetServiceBase* service_;
  FleetRegistry* registry_;
  JobService* jobs_;
  std::unique_ptr<grpc::ServerCompletionQueue> cq_;
  std::thread thread_;
  grpc::Alarm wake_alarm_;
  std::atomic<bool> wake_pending_{false};
  std::atomic<bool> fleet_dirty_{false};
  std::atomic<int> fleet_watchers_{0};  ///< read by OnFleetChanged without a lock
  std::atomic<int> job_watchers_{0};
  bool shut_down_ = false;

  absl::Mutex signal_mutex_;  ///< guards what other threads hand to the hub thread
  bool stopping_ ABSL_GUARDED_BY(signal_mutex_) = false;
  std::set<std::string> dirty_jobs_ ABSL_GUARDED_BY(signal_mutex_);
  int live_ ABSL_GUARDED_BY(signal_mutex_) = 0;  ///< streams (and awaited calls) not yet gone

  // Touched only by the hub thread.
  std::set<FleetWatcher*> fleet_;
  std::multimap<std::string, JobWatcher*> jobs_by_id_;
};

}  // namespace fleetnav::server
