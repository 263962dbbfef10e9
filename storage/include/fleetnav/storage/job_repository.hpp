#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/job.hpp"

namespace fleetnav::storage {

using ::fleetnav::JobFilter;

struct JobPage {
  std::vector<Job> jobs;        ///< oldest first
  std::string next_page_token;  ///< empty on the last page
};

struct CreatedJob {
  Job job;
  bool deduplicated = false;  ///< the idempotency key named an existing job, returned as is
};

/// Jobs and their ordered events. CreateJob assigns the job id ("job-000001", …) and is
/// idempotent on a non-empty idempotency key; every state change is stored together with its
/// event in one transaction, so the events always explain the state. Thread-safe.
class JobRepository {
 public:
  virtual ~JobRepository() = default;
  /// Stores `job` (its id is assigned) with its first event (its sequence is assigned).
  virtual absl::StatusOr<CreatedJob> CreateJob(Job job, JobEvent first_event) = 0;
  virtual absl::StatusOr<Job> GetJob(const std::string& job_id) = 0;
  virtual absl::StatusOr<JobPage> ListJobs(const JobFilter& filter) = 0;
  /// How many jobs are in each state (states without a job are left out).
  virtual absl::StatusOr<std::map<JobState, int64_t>> CountJobsByState() = 0;
  /// Replaces the stored job with `job` and appends `event` (sequence assigned, returned).
  /// NotFound for an unknown job.
  virtual absl::StatusOr<int64_t> UpdateJob(const Job& job, JobEvent event) = 0;
  /// Events with sequence > after_sequence, in order.
  virtual absl::StatusOr<std::vector<JobEvent>> ListEvents(const std::string& job_id,
                                                           int64_t after_sequence) = 0;
};

}  // namespace fleetnav::storage
