#include "fleetnav/robot_agent/agent.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/robot_agent/laser_filters.hpp"

namespace fleetnav::agent {

absl::Status AgentParams::Validate() const {
  if (!(telemetry_period_s > 0.0 && telemetry_period_s <= 0.1)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "telemetry_period_s: must be in (0, 0.1] (at least 10 Hz), got ", telemetry_period_s));
  }
  if (settle_ticks < 0) return absl::InvalidArgumentError("settle_ticks: must be >= 0");
  if (!(std::isfinite(ultrasonic_range_max_m) && ultrasonic_range_max_m > 0.0)) {
    return absl::InvalidArgumentError("ultrasonic_range_max_m: must be finite and > 0");
  }
  if (!(std::isfinite(load_mask_margin_m) && load_mask_margin_m >= 0.0)) {
    return absl::InvalidArgumentError("load_mask_margin_m: must be finite and >= 0");
  }
  RETURN_IF_ERROR(modes.Validate());
  return safety.Validate();
}

Agent::Agent(RouteContext context, AgentPorts ports, std::optional<Route> route, AgentParams params)
    : context_(std::move(context)),
      ports_(ports),
      params_(params),
      perception_(context_.model, params.ultrasonic_range_max_m),
      safety_(params.safety) {
  if (route) StartRoute(std::move(*route));
}

void Agent::StartRoute(Route route, const RoutePosition& from) {
  const Pose2 here = localizer().estimate().pose_in_map;
  executor_.emplace(std::move(route), context_, params_.modes, here, from);
  reported_action_ = -1;
  // Actions before the resume point were reported finished by the agent that ran them.
  finished_action_ = from.action_index - 1;
  paused_ = false;
  end_reported_ = false;
  safety_.Reset();
}

void Agent::Report(JobEventType type, int action_index, NavigationMode mode,
                   const std::string& reason, AgentResult* result) {
  JobEvent event;
  event.job_id = current_job_id_;
  event.type = type;
  event.action_index = action_index;
  event.mode = mode;
  event.reason = reason;
  result->events.push_back(event);
  if (ports_.jobs != nullptr && !current_job_id_.empty()) ports_.jobs->ReportEvent(event);
}

void Agent::ReportProgress(const ExecutorOutput& output, AgentResult* result) {
  // An action is reported finished once: when the next starts, or at once when the next waits
  // for traffic (the robots waiting for this one may go).
  auto finish = [&](int index) {
    if (index >= 0 && index != finished_action_) {
      Report(JobEventType::kActionFinished, index, output.mode, "", result);
      finished_action_ = index;
    }
  };
  if (output.waiting) {
    finish(output.action_index);
  } else if (output.action_index >= 0 && output.action_index != reported_action_) {
    finish(reported_action_);
    Report(JobEventType::kActionStarted, output.action_index, output.mode, "", result);
    reported_action_ = output.action_index;
  }
  if (!output.mode_reason.empty()) {
    Report(JobEventType::kModeSwitch, output.action_index, output.mode, output.mode_reason, result);
  }
}

void Agent::ApplyCommand(const JobCommand& command, const ExecutorOutput& output,
                         AgentResult* result) {
  if (command.job_id != current_job_id_ || current_job_id_.empty()) return;
  if (command.type == JobCommandType::kPause) paused_ = true;
  if (command.type == JobCommandType::kResume) paused_ = false;
  if (command.type == JobCommandType::kClearance && executor_) {
    // The action under way stays cleared whatever a new session says.
    executor_->SetClearedUpTo(std::max(command.cleared_up_to_action, executor_->action_index()));
    executor_->SetHold(command.hold);
  }
  if (command.type == JobCommandType::kCancel) {
    Report(JobEventType::kCancelled, output.action_index, NavigationMode::kIdle, command.reason,
           result);
    executor_.reset();
    current_job_id_.clear();
    ports_.jobs->SetCurrentJob("");
    ++result->jobs_finished;
  }
}

void Agent::ServeJobs(const ExecutorOutput& output, AgentResult* result) {
  const std::vector<JobCommand> commands = ports_.jobs->TakeCommands();
  for (const JobCommand& command : commands) {
    // Kept, for a clearance may come before the agent takes its job's assignment.
    if (command.type == JobCommandType::kClearance) clearance_ = command;
    ApplyCommand(command, output, result);
  }
  if (!current_job_id_.empty() && executor_ && executor_->state() != ExecutionState::kRunning) {
    executor_.reset();
    current_job_id_.clear();
    ports_.jobs->SetCurrentJob("");
    ++result->jobs_finished;
  }
  if (current_job_id_.empty()) {
    if (std::optional<JobAssignment> assignment = ports_.jobs->TakeAssignment()) {
      current_job_id_ = assignment->job.job_id;
      ports_.jobs->SetCurrentJob(current_job_id_);
      if (absl::Status site = PrepareSite(*assignment); !site.ok()) {
        // Nothing moves: the job fails at once with the reason.
        StartRoute(Route{});
        executor_->Abort(site);
        return;
      }
      StartRoute(*assignment->route, assignment->resume);
      // A job from the server waits for its traffic clearance.
      const bool cleared = clearance_.job_id == current_job_id_;
      executor_->SetClearedUpTo(cleared ? clearance_.cleared_up_to_action : -1);
      executor_->SetHold(cleared ? clearance_.hold : std::nullopt);
      // Commands about this job that came with it (a job sent again while an operator holds
      // it comes with PAUSE).
      for (const JobCommand& command : commands) {
        if (command.type != JobCommandType::kClearance) ApplyCommand(command, output, result);
      }
    }
  }
}

absl::Status Agent::PrepareSite(const JobAssignment& assignment) {
  const std::string& map_id = assignment.job.map_id;
  if (ports_.sites == nullptr || !ports_.make_localizer || map_id.empty()) {
    return absl::OkStatus();
  }
  const std::string key =
      absl::StrCat(map_id, "@", assignment.map_version, "/", assignment.marker_set_version);
  if (key == site_key_) return absl::OkStatus();
  absl::StatusOr<SiteData> site =
      ports_.sites->Load(map_id, assignment.map_version, assignment.marker_set_version);
  if (!site.ok()) {
    return absl::FailedPreconditionError(
        absl::StrCat("map ", map_id, " v", assignment.map_version,
                     " could not be loaded on the robot: ", site.status().message()));
  }
  absl::StatusOr<std::unique_ptr<localization::Localizer>> made =
      ports_.make_localizer(*site, localizer().estimate().pose_in_map);
  if (!made.ok()) {
    return absl::FailedPreconditionError(
        absl::StrCat("cannot localize on map ", map_id, ": ", made.status().message()));
  }
  job_localizer_ = *std::move(made);
  context_.map = site->map;
  context_.markers = site->markers;
  context_.moved_loads = {};  // places on the map the agent worked on before
  site_key_ = key;
  return absl::OkStatus();
}

void Agent::MaskLoad(const Eigen::Vector2d& load_size_m, SensorFrame* frame) const {
  // The trolley's legs stand at its corners: the box reaches a little beyond them.
  const Eigen::Vector2d half =
      0.5 * load_size_m + Eigen::Vector2d::Constant(params_.load_mask_margin_m);
  const Eigen::AlignedBox2d load(-half, half);
  for (LaserScanSample& scan : frame->lasers) {
    if (const SensorMount* mount = context_.model.FindSensor(scan.name)) {
      MaskCarriedLoad(load, mount->pose_in_base, &scan);
    }
  }
}

Telemetry Agent::MakeTelemetry(int64_t stamp_ns, const ExecutorOutput& output) const {
  const localization::LocalizerEstimate& estimate = localizer().estimate();
  Telemetry t;
  t.stamp_ns = stamp_ns;
  t.pose_in_odom = estimate.pose_in_odom;
  t.pose_in_map = estimate.pose_in_map;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      t.covariance[static_cast<size_t>(r * 3 + c)] = estimate.covariance(r, c);
  }
  t.velocity = estimate.velocity;
  t.mode = output.mode;
  t.localization_confidence = estimate.confidence;
  t.localization_lost = estimate.lost;
  t.battery_fraction = battery_fraction_;
  t.action_index = output.action_index;
  t.job_progress_fraction = output.progress_fraction;
  t.action_progress_fraction = output.action_fraction;
  t.carried_load_m = context_.carried_load_m;
  return t;
}

absl::StatusOr<AgentResult> Agent::Run() {
  RETURN_IF_ERROR(params_.Validate());
  if (ports_.hal == nullptr || ports_.localizer == nullptr || ports_.telemetry == nullptr) {
    return absl::InvalidArgumentError("agent ports: hal, localizer and telemetry are required");
  }
  AgentResult result;
  int64_t next_telemetry_ns = 0;
  int settle_remaining = params_.settle_ticks;
  int64_t last_stamp_ns = -1;
  int64_t first_stamp_ns = -1;
  while (true) {
    ASSIGN_OR_RETURN(std::optional<SensorFrame> frame, ports_.hal->NextFrame());
    if (!frame) break;  // the hardware or simulation ended
    // In a simulated run's lockstep, what the server sent for the last tick is in before this
    // one is worked on.
    if (ports_.jobs != nullptr) ports_.jobs->BeginTick();
    ++result.ticks;
    const double dt_s =
        last_stamp_ns < 0 ? frame->control_period_s : (frame->stamp_ns - last_stamp_ns) * 1e-9;
    last_stamp_ns = frame->stamp_ns;
    if (first_stamp_ns < 0) first_stamp_ns = frame->stamp_ns;
    if (context_.carried_load_m) MaskLoad(*context_.carried_load_m, &*frame);
    RETURN_IF_ERROR(localizer().Update(*frame));
    if (frame->battery_fraction) battery_fraction_ = *frame->battery_fraction;
    const localization::LocalizerEstimate& estimate = localizer().estimate();
    std::vector<int> detected_markers;
    for (localization::MarkerCalibration& c : localizer().TakeCalibrations()) {
      detected_markers.push_back(c.marker_id);
      result.calibrations.push_back(std::move(c));
    }
    ControlInput input;
    input.pose_in_map = estimate.pose_in_map;
    input.pose_in_odom = estimate.pose_in_odom;
    input.velocity = estimate.velocity;
    input.perception = perception_.Build(*frame);
    input.dt_s = dt_s;

    ExecutorOutput output;
    const std::string job_for_telemetry = current_job_id_;
    if (executor_ && executor_->state() == ExecutionState::kRunning) {
      const SafetyVerdict& verdict =
          safety_.Check(input.perception, last_command_, estimate.velocity, estimate.lost, dt_s,
                        estimate.lost_reason);
      if (verdict.stop != SafetyStop::kNone) {
        result.safety_stop = verdict.stop;
        if (verdict.stop == SafetyStop::kBumper) {
          Report(JobEventType::kBumper, executor_->action_index(), NavigationMode::kFault,
                 verdict.reason, &result);
        } else if (verdict.stop == SafetyStop::kLocalizationLost) {
          Report(JobEventType::kLocalizationLost, executor_->action_index(), NavigationMode::kFault,
                 verdict.reason, &result);
        }
        executor_->Abort(absl::AbortedError(verdict.reason));
      }
      const bool was_running = executor_->state() == ExecutionState::kRunning;
      if (was_running && !paused_) {
        output = executor_->Step(input, detected_markers);
        ReportProgress(output, &result);
      } else {
        output = executor_->Step(input, {});  // reports the state, commands nothing
      }
    } else if (executor_) {
      output = executor_->Step(input, {});
    }
    if (executor_) {
      lift_raised_ = output.lift_raised;
      // What the route has done to the site outlives it (a cancel resets the executor at once).
      context_.carried_load_m = output.carried_load_m;
      context_.moved_loads = executor_->moved_loads();
    }
    if (executor_ && executor_->state() != ExecutionState::kRunning && !end_reported_) {
      end_reported_ = true;
      if (executor_->state() == ExecutionState::kSucceeded) {
        if (output.action_index >= 0) {
          Report(JobEventType::kActionFinished, output.action_index, NavigationMode::kIdle, "",
                 &result);
        }
        Report(JobEventType::kSucceeded, output.action_index, NavigationMode::kIdle, "", &result);
      } else {
        Report(JobEventType::kFailed, executor_->action_index(), NavigationMode::kFault,
               std::string(executor_->failure().message()), &result);
      }
    }
    if (paused_) {
      output.mode = NavigationMode::kPaused;
      output.command = Twist2{};
    }
    last_command_ = output.command;
    if (ports_.jobs != nullptr) ServeJobs(output, &result);
    if (frame->stamp_ns >= next_telemetry_ns) {
      Telemetry telemetry = MakeTelemetry(frame->stamp_ns, output);
      telemetry.sequence = ++sequence_;
      telemetry.job_id = job_for_telemetry;
      ports_.telemetry->Publish(telemetry);
      ++result.telemetry_sent;
      // Schedule from the due time, not the frame time, so the rate holds whatever the tick.
      const int64_t period_ns =
          static_cast<int64_t>(std::llround(params_.telemetry_period_s * 1e9));
      next_telemetry_ns = std::max(next_telemetry_ns + period_ns, frame->stamp_ns - period_ns / 2);
    }
    // In a simulated run's lockstep the server takes in this tick while the simulator steps.
    if (ports_.jobs != nullptr) ports_.jobs->EndTick(*frame);
    ActuatorCommand command;
    command.tick = frame->tick;
    command.drive = output.command;
    command.lift_raised = lift_raised_;
    RETURN_IF_ERROR(ports_.hal->Send(command));

    if (ports_.jobs != nullptr) {
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
  result.final_pose_in_map = localizer().estimate().pose_in_map;
  if (first_stamp_ns >= 0) result.sim_time_s = (last_stamp_ns - first_stamp_ns) * 1e-9;
  return result;
}

}  // namespace fleetnav::agent
