#pragma once

#include <functional>
#include <string>
#include <vector>

#include "fleetnav/storage/job_repository.hpp"

namespace fleetnav::server {

/// A JobRepository that, after each job or event it stores, tells a listener which job changed,
/// and an event listener the job and event stored. It is where WatchJob streams learn of new
/// events, so that they are woken by changes instead of polling the store, and where fleetnavd
/// logs each job transition. Everything else passes through to the wrapped repository.
/// Thread-safe as that repository is; the listeners are set once before serving and must be
/// quick.
class NotifyingJobRepository final : public storage::JobRepository {
 public:
  using Listener = std::function<void(const std::string& job_id)>;

  explicit NotifyingJobRepository(storage::JobRepository* inner) : inner_(inner) {}
  using EventListener = std::function<void(const Job& job, const JobEvent& event)>;

  explicit NotifyingJobRepository(storage::JobRepository* inner, EventListener on_event)
      : inner_(inner), on_event_(std::move(on_event)) {}
  void SetListener(Listener listener) { listener_ = std::move(listener); }

  absl::StatusOr<storage::CreatedJob> CreateJob(Job job, JobEvent first_event) override;
  absl::StatusOr<Job> GetJob(const std::string& job_id) override;
  absl::StatusOr<storage::JobPage> ListJobs(const storage::JobFilter& filter) override;
  absl::StatusOr<std::map<JobState, int64_t>> CountJobsByState() override {
    return inner_->CountJobsByState();
  }
  absl::StatusOr<int64_t> UpdateJob(const Job& job, JobEvent event) override;
  absl::StatusOr<std::vector<JobEvent>> ListEvents(const std::string& job_id,
                                                   int64_t after_sequence) override;

 private:
  storage::JobRepository* inner_;
  Listener listener_;
  EventListener on_event_;
};

}  // namespace fleetnav::server
