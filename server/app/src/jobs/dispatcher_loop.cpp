#include "fleetnav/server/jobs/dispatcher_loop.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>

#include "absl/time/time.h"

namespace fleetnav::server {
namespace {

/// CPU time of the calling thread (a computing-time measure, not a clock of the logic).
double ThreadCpuMs() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) * 1e-6;
}

}  // namespace

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

void DispatcherLoop::RunPass() {
  // Computing time of the pass: a steady clock is right here, whatever clock the jobs use.
  const auto start = std::chrono::steady_clock::now();
  const double start_cpu_ms = ThreadCpuMs();
  const int assigned = jobs_->DispatchOnce();
  if (assigned > 0) {
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    assigning_.Add(ms);
    if (on_assigning_pass_) on_assigning_pass_(ms / 1000.0);
    if (assigned == 1) {
      one_job_.Add(ms);
      one_job_cpu_.Add(ThreadCpuMs() - start_cpu_ms);
    }
  }
}

void DispatcherLoop::Start() {
  thread_ = std::thread([this] {
    while (!stopping_.load() && !taken_over_.load()) {
      RunPass();
      jobs_->WaitForWork(absl::Seconds(period_s_));
    }
  });
}

void DispatcherLoop::TakeOver() {
  if (taken_over_.exchange(true)) return;
  jobs_->WakeDispatcher();
  if (thread_.joinable()) thread_.join();
  next_pass_ns_.reset();  // the first tick runs a pass: a wake the thread took is not lost
}

void DispatcherLoop::RunPassIfDue(int64_t sim_time_ns) {
  const bool woken = jobs_->TakeWork();
  if (!woken && next_pass_ns_ && sim_time_ns < *next_pass_ns_) return;
  RunPass();
  next_pass_ns_ = sim_time_ns + static_cast<int64_t>(period_s_ * 1e9);
}

void DispatcherLoop::Stop() {
  if (stopping_.exchange(true)) return;
  jobs_->WakeDispatcher();
  if (thread_.joinable()) thread_.join();
}

}  // namespace fleetnav::server
