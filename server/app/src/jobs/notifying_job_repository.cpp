#include "fleetnav/server/jobs/notifying_job_repository.hpp"

namespace fleetnav::server {

absl::StatusOr<storage::CreatedJob> NotifyingJobRepository::CreateJob(Job job,
                                                                      JobEvent first_event) {
  absl::StatusOr<storage::CreatedJob> created = inner_->CreateJob(std::move(job), first_event);
  if (!created.ok() || created->deduplicated) return created;
  if (listener_) listener_(created->job.job_id);
  if (on_event_) {
    first_event.job_id = created->job.job_id;
    on_event_(created->job, first_event);
  }
  return created;
}

absl::StatusOr<Job> NotifyingJobRepository::GetJob(const std::string& job_id) {
  return inner_->GetJob(job_id);
}

absl::StatusOr<storage::JobPage> NotifyingJobRepository::ListJobs(
    const storage::JobFilter& filter) {
  return inner_->ListJobs(filter);
}

absl::StatusOr<int64_t> NotifyingJobRepository::UpdateJob(const Job& job, JobEvent event) {
  absl::StatusOr<int64_t> sequence = inner_->UpdateJob(job, event);
  if (!sequence.ok()) return sequence;
  if (listener_) listener_(job.job_id);
  if (on_event_) on_event_(job, event);
  return sequence;
}

absl::StatusOr<std::vector<JobEvent>> NotifyingJobRepository::ListEvents(const std::string& job_id,
                                                                         int64_t after_sequence) {
  return inner_->ListEvents(job_id, after_sequence);
}

}  // namespace fleetnav::server
