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
    : ports_(ports),
      params_(params),
      perception_(context.model, params.ultrasonic_range_max_m),
      self_filter_(context.model, params.load_mask_margin_m),
      runner_(std::move(context),
              JobRunnerPorts{ports.jobs, ports.sites, ports.make_localizer, ports.localizer},
              params.modes, params.safety, std::move(route)) {}

Telemetry Agent::MakeTelemetry(int64_t stamp_ns, const ExecutorOutput& output) const {
  const localization::LocalizerEstimate& estimate = runner_.localizer().estimate();
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
  t.carried_load_m = runner_.carried_load_m();
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
    // What the robot carries is no landmark and no obstacle: out before anything reads it.
    self_filter_.Apply(runner_.carried_load_m(), &*frame);
    localization::Localizer& localizer = runner_.localizer();
    RETURN_IF_ERROR(localizer.Update(*frame));
    if (frame->battery_fraction) battery_fraction_ = *frame->battery_fraction;
    const localization::LocalizerEstimate& estimate = localizer.estimate();
    std::vector<int> detected_markers;
    for (localization::MarkerCalibration& c : localizer.TakeCalibrations()) {
      detected_markers.push_back(c.marker_id);
      result.calibrations.push_back(std::move(c));
    }
    ControlInput input;
    input.pose_in_map = estimate.pose_in_map;
    input.pose_in_odom = estimate.pose_in_odom;
    input.velocity = estimate.velocity;
    input.perception = perception_.Build(*frame);
    input.dt_s = dt_s;

    const std::string job_for_telemetry = runner_.job_id();
    const ExecutorOutput output = runner_.Step(input, detected_markers, estimate, last_command_);
    last_command_ = output.command;
    runner_.Serve(output);
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
    command.lift_raised = runner_.lift_raised();
    RETURN_IF_ERROR(ports_.hal->Send(command));

    if (ports_.jobs != nullptr) {
      if (params_.max_jobs > 0 && runner_.jobs_finished() >= params_.max_jobs &&
          settle_remaining-- <= 0) {
        break;
      }
      continue;
    }
    result.state = runner_.state();
    if (result.state != ExecutionState::kRunning && params_.exit_when_done &&
        settle_remaining-- <= 0) {
      break;
    }
  }
  if (const absl::Status failure = runner_.failure(); !failure.ok()) {
    result.failure_reason = std::string(failure.message());
  }
  result.events = runner_.events();
  result.jobs_finished = runner_.jobs_finished();
  result.safety_stop = runner_.safety_stop();
  result.final_pose_in_map = runner_.localizer().estimate().pose_in_map;
  if (first_stamp_ns >= 0) result.sim_time_s = (last_stamp_ns - first_stamp_ns) * 1e-9;
  return result;
}

}  // namespace fleetnav::agent
