#include "fleetnav/server/jobs/job_ledger.hpp"

#include <cmath>

namespace fleetnav::server {

absl::StatusOr<storage::CreatedJob> JobLedger::Create(Job job) {
  job.created_unix_ms = job.updated_unix_ms = NowUnixMs();
  job.state = JobState::kQueued;
  return jobs_->CreateJob(job, MakeEvent(job, JobEventType::kQueued, "", ""));
}

absl::Status JobLedger::Transition(Job& job, JobState state, JobEventType type,
                                   const std::string& reason, const std::string& robot_id) {
  job.state = state;
  job.updated_unix_ms = NowUnixMs();
  if (!reason.empty()) job.reason = reason;
  if (IsTerminal(state)) {
    absl::MutexLock lock(&progress_mutex_);
    progress_decile_.erase(job.job_id);
  }
  return jobs_->UpdateJob(job, MakeEvent(job, type, reason, robot_id)).status();
}

absl::Status JobLedger::Record(const Job& job, const JobEvent& event) {
  return jobs_->UpdateJob(job, event).status();
}

JobEvent JobLedger::MakeEvent(const Job& job, JobEventType type, const std::string& reason,
                              const std::string& robot_id) const {
  JobEvent event;
  event.job_id = job.job_id;
  event.type = type;
  event.unix_ms = NowUnixMs();
  event.robot_id = robot_id;
  event.progress_fraction = job.progress_fraction;
  event.reason = reason;
  event.state = job.state;
  return event;
}

namespace {
int Decile(double fraction) { return static_cast<int>(std::floor(fraction * 10.0)); }
}  // namespace

bool JobLedger::IsNewProgressStep(const std::string& job_id, double fraction) const {
  absl::MutexLock lock(&progress_mutex_);
  auto it = progress_decile_.find(job_id);
  return it == progress_decile_.end() || Decile(fraction) > it->second;
}

void JobLedger::NoteProgressStored(const std::string& job_id, double fraction) {
  absl::MutexLock lock(&progress_mutex_);
  progress_decile_[job_id] = Decile(fraction);
}

}  // namespace fleetnav::server
