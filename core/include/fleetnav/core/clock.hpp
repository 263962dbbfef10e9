#pragma once

#include <cstdint>

#include "absl/synchronization/mutex.h"

namespace fleetnav {

/// A source of time: NowNs for intervals and timeouts (monotonic), UnixMs for the calendar
/// stamps of stored records (a job's creation, a map's upload). In a simulated run the
/// simulator's clock is the only time source (Lely thesis §6.1, "time source module"), so both
/// count simulated time; elsewhere it is the system clock. Implementations are thread-safe.
class Clock {
 public:
  virtual ~Clock() = default;
  virtual int64_t NowNs() const = 0;
  /// Milliseconds since 1970-01-01 UTC.
  virtual int64_t UnixMs() const = 0;
  double NowS() const { return static_cast<double>(NowNs()) * 1e-9; }
};

/// Monotonic wall time (std::chrono::steady_clock) and the calendar (system_clock).
class SystemClock final : public Clock {
 public:
  int64_t NowNs() const override;
  int64_t UnixMs() const override;
};

/// A clock that only moves when told to, for simulation and tests. Time never goes backwards:
/// SetNs with an earlier time is ignored. Its calendar reads unix_ms_at_zero plus the time
/// set, so a server on the simulator's clock stamps records at the simulation's calendar start
/// (SetUnixMsAtZero, from the simulator) plus simulated time. Thread-safe.
class ManualClock final : public Clock {
 public:
  explicit ManualClock(int64_t start_ns = 0, int64_t unix_ms_at_zero = 0)
      : unix_ms_at_zero_(unix_ms_at_zero), now_ns_(start_ns) {}
  int64_t NowNs() const override;
  int64_t UnixMs() const override;
  void AdvanceNs(int64_t delta_ns);
  void SetNs(int64_t now_ns);
  /// The calendar at time 0 (ms since 1970-01-01 UTC).
  void SetUnixMsAtZero(int64_t unix_ms);

 private:
  mutable absl::Mutex mutex_;
  int64_t unix_ms_at_zero_ ABSL_GUARDED_BY(mutex_);
  int64_t now_ns_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav
