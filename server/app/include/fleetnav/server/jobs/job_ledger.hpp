#pragma once

#include <map>
#include <string>

#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/job.hpp"
#include "fleetnav/storage/job_repository.hpp"

namespace fleetnav::server {

/// The job store as the job services write it: every state change is stored together with its
/// event, stamped by the injected clock (simulated time in a simulated run), and progress is
/// kept in steps of 10 % so that telemetry at 10 Hz does not become a write per message. Reads
/// (Get, List, Events) and the progress steps are thread-safe; JobService serialises the
/// writes.
class JobLedger {
 public:
  JobLedger(storage::JobRepository* jobs, const Clock* clock) : jobs_(jobs), clock_(clock) {}

  absl::StatusOr<Job> Get(const std::string& job_id) const { return jobs_->GetJob(job_id); }
  absl::StatusOr<storage::JobPage> List(const storage::JobFilter& filter) const {
    return jobs_->ListJobs(filter);
  }
  absl::StatusOr<std::vector<JobEvent>> Events(const std::string& job_id,
                                               int64_t after_sequence) const {
    return jobs_->ListEvents(job_id, after_sequence);
  }
  /// Stores a new queued job (or returns the one with the same idempotency key).
  absl::StatusOr<storage::CreatedJob> Create(Job job);

  /// Sets the job's state (and its reason when one is given) and stores it with an event of
  /// `type` naming `robot_id`.
  absl::Status Transition(Job& job, JobState state, JobEventType type, const std::string& reason,
                          const std::string& robot_id);
  /// Stores `event` with the job as it is (an event that changes no state).
  absl::Status Record(const Job& job, const JobEvent& event);
  /// An event of `job` stamped now, with its state and progress.
  JobEvent MakeEvent(const Job& job, JobEventType type, const std::string& reason,
                     const std::string& robot_id) const;

  /// Whether a report of `fraction` done reaches a 10 % step of the job not yet stored.
  bool IsNewProgressStep(const std::string& job_id, double fraction) const;
  /// Notes that the job's progress at `fraction` is stored.
  void NoteProgressStored(const std::string& job_id, double fraction);

  int64_t NowUnixMs() const { return clock_->UnixMs(); }

 private:
  storage::JobRepository* jobs_;
  const Clock* clock_;
  /// Its own lock, so that telemetry that reaches no new step never waits for JobService's.
  mutable absl::Mutex progress_mutex_;
  std::map<std::string, int> progress_decile_ ABSL_GUARDED_BY(progress_mutex_);  ///< by job id
};

}  // namespace fleetnav::server
