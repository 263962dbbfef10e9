#pragma once

#include <utility>

#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"

namespace fleetnav::server {

/// Wakes the dispatcher when there may be work for it (a job submitted or ended, a robot
/// freed), so that a job is dispatched when it can be rather than at the next period.
/// Thread-safe.
class WorkSignal {
 public:
  void Notify() {
    absl::MutexLock lock(&mutex_);
    pending_ = true;
  }
  /// Whether Notify came since the last wait or take; clears the signal.
  bool Take() {
    absl::MutexLock lock(&mutex_);
    return std::exchange(pending_, false);
  }
  /// Blocks until Notify or `timeout`, then clears the signal.
  void WaitFor(absl::Duration timeout) {
    absl::MutexLock lock(&mutex_);
    mutex_.AwaitWithTimeout(absl::Condition(&pending_), timeout);
    pending_ = false;
  }

 private:
  absl::Mutex mutex_;
  bool pending_ ABSL_GUARDED_BY(mutex_) = false;
};

}  // namespace fleetnav::server
