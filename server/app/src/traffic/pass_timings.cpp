#include "fleetnav/server/traffic/pass_timings.hpp"

#include <time.h>

#include <algorithm>

namespace fleetnav::server {

double ThreadCpuMs() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) * 1e-6;
}

void PassTimings::Add(double ms) {
  if (ms_.size() < capacity_) {
    ms_.push_back(ms);
  } else {
    ms_[static_cast<size_t>(count_) % capacity_] = ms;
  }
  ++count_;
}

PassFigures PassTimings::Figures() const {
  PassFigures figures;
  figures.count = count_;
  if (ms_.empty()) return figures;
  std::vector<double> sorted = ms_;
  std::sort(sorted.begin(), sorted.end());
  const auto at = [&](double q) {
    return sorted[std::min(sorted.size() - 1,
                           static_cast<size_t>(q * static_cast<double>(sorted.size())))];
  };
  figures.p50_ms = at(0.5);
  figures.p99_ms = at(0.99);
  figures.max_ms = sorted.back();
  return figures;
}

}  // namespace fleetnav::server
