#include "fleetnav/server/jobs/dispatcher_loop.hpp"

#include <algorithm>
#include <chrono>

#include "absl/time/time.h"

namespace fleetnav::server {

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
  const bool searched = traffic_ != nullptr && traffic_->SearchesPending();
  if (!woken && !searched && next_pass_ns_ && sim_time_ns < *next_pass_ns_) return;
  if (searched) traffic_->WaitForSearches();
  RunPass();
  next_pass_ns_ = sim_time_ns + static_cast<int64_t>(period_s_ * 1e9);
}

void DispatcherLoop::Stop() {
  if (stopping_.exchange(true)) return;
  jobs_->WakeDispatcher();
  if (thread_.joinable()) thread_.join();
}

}  // namespace fleetnav::server
