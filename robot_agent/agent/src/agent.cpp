#include "fleetnav/robot_agent/agent.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::agent {

absl::Status AgentParams::Validate() const {
  if (!(telemetry_period_s > 0.0 && telemetry_period_s <= 0.1)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "telemetry_period_s: must be in (0, 0.1] (at least 10 Hz), got ", telemetry_period_s));
  }
  if (!initial_pose_in_map.IsFinite()) {
    return absl::InvalidArgumentError("initial_pose_in_map: must be finite");
  }
  if (settle_ticks < 0) return absl::InvalidArgumentError("settle_ticks: must be >= 0");
  return absl::OkStatus();
}

Agent::Agent(const RobotModel& model, RobotHal* hal, TelemetrySink* telemetry,
             std::optional<Route> route, AgentParams params, JobChannel* jobs)
    : model_(model),
      hal_(hal),
      telemetry_(telemetry),
      params_(params),
      odometry_(model),
      jobs_(jobs) {
  if (route) executor_.emplace(std::move(*route));
}

void Agent::ReportJobEvent(JobEventType type, int action_index, const std::string& reason) {
  JobEvent event;
  event.job_id = current_job_id_;
  event.type = type;
  event.action_index = action_index;
  event.reason = reason;
  jobs_->ReportEvent(event);
}

void Agent::ServeJobs(const ExecutorOutput& output, int64_t stamp_ns, AgentResult* result) {
  (void)stamp_ns;
  for (const JobCommand& command : jobs_->TakeCommands()) {
    if (command.job_id != current_job_id_ || current_job_id_.empty()) continue;
    if (command.type == JobCommandType::kPause) paused_ = true;
    if (command.type == JobCommandType::kResume) paused_ = false;
    if (command.type == JobCommandType::kCancel) {
      ReportJobEvent(JobEventType::kCancelled, output.action_index, command.reason);
      executor_.reset();
      current_job_id_.clear();
      jobs_->SetCurrentJob("");
      ++result->jobs_finished;
    }
  }
  if (!current_job_id_.empty() && executor_) {
    if (output.action_index != reported_action_ && output.action_index >= 0) {
      if (reported_action_ >= 0) {
        ReportJobEvent(JobEventType::kActionFinished, reported_action_, "");
      }
      ReportJobEvent(JobEventType::kActionStarted, output.action_index, "");
      reported_action_ = output.action_index;
    }
    if (executor_->state() != ExecutionState::kRunning) {
      const bool succeeded = executor_->state() == ExecutionState::kSucceeded;
      if (succeeded && reported_action_ >= 0) {
        ReportJobEvent(JobEventType::kActionFinished, reported_action_, "");
      }
      ReportJobEvent(succeeded ? JobEventType::kSucceeded : JobEventType::kFailed, reported_action_,
                     succeeded ? "" : std::string(executor_->failure().message()));
      executor_.reset();
      current_job_id_.clear();
      jobs_->SetCurrentJob("");
      ++result->jobs_finished;
    }
  }
  if (current_job_id_.empty()) {
    if (std::optional<JobAssignment> assignment = jobs_->TakeAssignment()) {
      current_job_id_ = assignment->job.job_id;
      reported_action_ = -1;
      paused_ = false;
      executor_.emplace(std::move(assignment->route));
      jobs_->SetCurrentJob(current_job_id_);
    }
  }
}

Telemetry Agent::MakeTelemetry(int64_t stamp_ns, const ExecutorOutput& output) const {
  Telemetry t;
  t.stamp_ns = stamp_ns;
  t.pose_in_odom = odometry_.pose_in_odom();
  t.pose_in_map = params_.initial_pose_in_map * odometry_.pose_in_odom();
  // Dead reckoning: uncertainty grows with distance (1 % of distance, 0.5° per metre).
  const double d = odometry_.distance_travelled_m();
  t.covariance = {std::pow(0.01 * d, 2),  0, 0, 0, std::pow(0.01 * d, 2), 0, 0, 0,
                  std::pow(0.0087 * d, 2)};
  t.velocity = odometry_.velocity();
  t.mode = output.mode;
  t.localization_confidence = 1.0 / (1.0 + 0.05 * d);
  t.battery_fraction = 1.0;
  t.action_index = output.action_index;
  t.job_progress_fraction = output.progress_fraction;
  return t;
}

absl::StatusOr<AgentResult> Agent::Run() {
  RETURN_IF_ERROR(params_.Validate());
  AgentResult result;
  int64_t next_telemetry_ns = 0;
  int settle_remaining = params_.settle_ticks;
  int64_t last_stamp_ns = -1;
  while (true) {
    ASSIGN_OR_RETURN(std::optional<SensorFrame> frame, hal_->NextFrame());
    if (!frame) break;  // the hardware or simulation ended
    ++result.ticks;
    odometry_.Update(*frame);
    const double dt_s =
        last_stamp_ns < 0 ? frame->control_period_s : (frame->stamp_ns - last_stamp_ns) * 1e-9;
    last_stamp_ns = frame->stamp_ns;

    ExecutorOutput output;
    if (executor_ && !paused_) output = executor_->Step(odometry_.pose_in_odom(), dt_s);
    if (executor_ && executor_->state() == ExecutionState::kFailed) {
      output.mode = NavigationMode::kFault;  // keep reporting the fault while settling
    }
    if (paused_) output.mode = NavigationMode::kPaused;
    ActuatorCommand command;
    command.tick = frame->tick;
    command.drive = output.command;
    const std::string job_for_telemetry = current_job_id_;
    if (jobs_ != nullptr) ServeJobs(output, frame->stamp_ns, &result);
    RETURN_IF_ERROR(hal_->Send(command));

    if (frame->stamp_ns >= next_telemetry_ns) {
      Telemetry telemetry = MakeTelemetry(frame->stamp_ns, output);
      telemetry.sequence = ++sequence_;
      telemetry.job_id = job_for_telemetry;
      telemetry_->Publish(telemetry);
      ++result.telemetry_sent;
      // Schedule from the due time, not the frame time, so the rate holds whatever the tick.
      const int64_t period_ns =
          static_cast<int64_t>(std::llround(params_.telemetry_period_s * 1e9));
      next_telemetry_ns = std::max(next_telemetry_ns + period_ns, frame->stamp_ns - period_ns / 2);
    }
    if (jobs_ != nullptr) {
      if (params_.max_jobs > 0 && result.jobs_finished >= params_.max_jobs &&
          settle_remaining-- <= 0) {
        break;
      }
      continue;
    }
    result.state = executor_ ? executor_->state() : ExecutionState::kRunning;
    if (result.state != ExecutionState::kRunning && params_.exit_when_done &&
        settle_remaining-- <= 0) {
      break;
    }
  }
  if (executor_ && !executor_->failure().ok()) {
    result.failure_reason = std::string(executor_->failure().message());
  }
  result.final_pose_in_map = params_.initial_pose_in_map * odometry_.pose_in_odom();
  return result;
}

}  // namespace fleetnav::agent
