#pragma once

#include <cstdint>

#include "absl/synchronization/mutex.h"

namespace fleetnav {

/// A source of time in nanoseconds. In a simulated run the simulator's clock is the only time
/// source (Lely thesis §6.1, "time source module"); elsewhere it is the system clock.
/// Implementations are thread-safe.
class Clock {
 public:
  virtual ~Clock() = default;
  virtual int64_t NowNs() const = 0;
  double NowS() const { return static_cast<double>(NowNs()) * 1e-9; }
};

/// Monotonic wall time (std::chrono::steady_clock).
class SystemClock final : public Clock {
 public:
  int64_t NowNs() const override;
};

/// A clock that only moves when told to, for simulation and tests. Time never goes backwards:
/// SetNs with an earlier time is ignored. Thread-safe.
class ManualClock final : public Clock {
 public:
  explicit ManualClock(int64_t start_ns = 0) : now_ns_(start_ns) {}
  int64_t NowNs() const override;
  void AdvanceNs(int64_t delta_ns);
  void SetNs(int64_t now_ns);

 private:
  mutable absl::Mutex mutex_;
  int64_t now_ns_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav
