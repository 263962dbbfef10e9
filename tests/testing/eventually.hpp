#pragma once

#include <chrono>
#include <functional>
#include <thread>

namespace fleetnav::testing {

/// Calls `attempt` every 100 ms until it returns true (then true) or `timeout_s` passed (then
/// false): for tests of processes, whose effects show after a while.
inline bool Eventually(const std::function<bool()>& attempt, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::milliseconds(static_cast<int64_t>(timeout_s * 1e3));
  while (std::chrono::steady_clock::now() < deadline) {
    if (attempt()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return false;
}

}  // namespace fleetnav::testing
