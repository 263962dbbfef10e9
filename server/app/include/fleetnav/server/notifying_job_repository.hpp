#pragma once

#include <functional>
#include <string>
#include <vector>

#include "fleetnav/storage/job_repository.hpp"

namespace fleetnav::server {

/// A JobRepository that, after each job or event it stores, tells a listener which job changed.
/// It is where WatchJob streams learn of new events, so that they are woken by changes instead of
/// polling the store. Everything else passes through to the wrapped repository. Thread-safe as
/// that repository is; the listener is set once before serving and must only signal.
class NotifyingJobRepository final : public storage::JobRepository {
 public:
  using Listener = std::function<void(const std::string& job_id)>;

  explicit NotifyingJobRepository(storage::JobRepository* inner) : inner_(inner) {}
  void SetListener(Listener listener) { listener_ = std::move(listener); }

  absl::StatusOr<storage::CreatedJob> CreateJob(Job job, JobEvent first_event) override;
  absl::StatusOr<Job> GetJob(const std::string& job_id) override;
  absl::StatusOr<storage::JobPage> ListJobs(const storage::JobFilter& filter) override;
  absl::StatusOr<int64_t> UpdateJob(const Job& job, JobEvent event) override;
  absl::StatusOr<std::vector<JobEvent>> ListEvents(const std::string& job_id,
                                                   int64_t after_sequence) override;

 private:
  storage::JobRepository* inner_;
  Listener listener_;
};

}  // namespace fleetnav::server
