#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <thread>
#include <vector>

#include "fleetnav/server/jobs/job_service.hpp"
#include "fleetnav/server/traffic/pass_timings.hpp"
#include "fleetnav/server/traffic/traffic_coordinator.hpp"

namespace fleetnav::server {

/// Runs JobService's dispatcher on a thread of its own: one pass (DispatchOnce), then a wait
/// until there may be work (a job submitted, a robot idle) or `period_s` passed. It times the
/// passes that assigned jobs — each is the assignment and traffic coordination replanned with
/// the new jobs — and separately those that assigned exactly one, the replanning latency when
/// a job is added, both in wall time and in the dispatcher thread's CPU time (which leaves out
/// the time other processes had the core: on a loaded machine the two differ). The dispatcher
/// only dispatches, so a submitted job waits for nothing else. In a simulated run's lockstep
/// the ticks take over (TakeOver): the thread ends, and each tick calls RunPassIfDue with its
/// sim time, so that the passes fall on the same ticks in every run.
/// Start once; Stop wakes and joins the thread.
class DispatcherLoop {
 public:
  /// `on_assigning_pass` (may be empty) is told each assigning pass's wall time in seconds, on
  /// the dispatcher's thread.
  DispatcherLoop(JobService* jobs, double period_s,
                 std::function<void(double seconds)> on_assigning_pass = {})
      : jobs_(jobs), period_s_(period_s), on_assigning_pass_(std::move(on_assigning_pass)) {}
  ~DispatcherLoop() { Stop(); }
  DispatcherLoop(const DispatcherLoop&) = delete;
  DispatcherLoop& operator=(const DispatcherLoop&) = delete;

  /// In lockstep a pass is due on every tick while `traffic` has searches not yet taken up,
  /// and it first waits for them (TrafficCoordinator::WaitForSearches), so that each search is
  /// taken up by the same pass in every run. Call before TakeOver.
  void SetTraffic(TrafficCoordinator* traffic) { traffic_ = traffic; }
  void Start();
  void Stop();
  /// Ends the thread; from now on only RunPassIfDue runs passes. Idempotent.
  void TakeOver();
  /// A pass when there may be work or `period_s` of sim time passed since the last one.
  void RunPassIfDue(int64_t sim_time_ns);
  /// Read after Stop (the figures belong to the thread, or the ticks, that run the passes).
  PassFigures assigning_passes() const { return assigning_.Figures(); }
  PassFigures one_job_passes() const { return one_job_.Figures(); }
  PassFigures one_job_pass_cpu() const { return one_job_cpu_.Figures(); }

 private:
  void RunPass();

  JobService* jobs_;
  double period_s_;
  std::function<void(double seconds)> on_assigning_pass_;
  TrafficCoordinator* traffic_ = nullptr;
  std::atomic<bool> stopping_{false};
  std::atomic<bool> taken_over_{false};
  std::thread thread_;
  std::optional<int64_t> next_pass_ns_;  ///< lockstep: when the next pass is due at the latest
  PassTimings assigning_;
  PassTimings one_job_;
  PassTimings one_job_cpu_;
};

}  // namespace fleetnav::server
