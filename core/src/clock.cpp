#include "fleetnav/core/clock.hpp"

#include <chrono>

namespace fleetnav {

int64_t SystemClock::NowNs() const {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

int64_t SystemClock::UnixMs() const {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

int64_t ManualClock::UnixMs() const {
  absl::MutexLock lock(&mutex_);
  return unix_ms_at_zero_ + now_ns_ / 1'000'000;
}

int64_t ManualClock::NowNs() const {
  absl::MutexLock lock(&mutex_);
  return now_ns_;
}

void ManualClock::AdvanceNs(int64_t delta_ns) {
  if (delta_ns <= 0) return;  // time never goes backwards
  absl::MutexLock lock(&mutex_);
  now_ns_ += delta_ns;
}

void ManualClock::SetNs(int64_t now_ns) {
  absl::MutexLock lock(&mutex_);
  if (now_ns > now_ns_) now_ns_ = now_ns;
}

void ManualClock::SetUnixMsAtZero(int64_t unix_ms) {
  absl::MutexLock lock(&mutex_);
  unix_ms_at_zero_ = unix_ms;
}

}  // namespace fleetnav
