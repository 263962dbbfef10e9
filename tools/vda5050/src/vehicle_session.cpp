#include "fleetnav/vda5050/vehicle_session.hpp"

#include <algorithm>

#include "absl/strings/str_cat.h"

namespace fleetnav::vda5050 {

bool VehicleSession::Fresh(const std::string& topic, uint32_t header_id) {
  const auto last = last_header_ids_.find(topic);
  if (last != last_header_ids_.end() && header_id <= last->second && header_id != 0) return false;
  last_header_ids_[topic] = header_id;
  return true;
}

JobEvent VehicleSession::Event(JobEventType type, int action_index,
                               const std::string& reason) const {
  JobEvent event;
  event.job_id = job_ ? job_->job_id : "";
  event.type = type;
  event.robot_id = robot_id_;
  event.action_index = action_index;
  event.mode = type == JobEventType::kActionStarted ? NavigationMode::kFreeNavigation
                                                    : NavigationMode::kIdle;
  event.reason = reason;
  return event;
}

Order VehicleSession::Start(const std::string& job_id, JobOrder order, int first_action) {
  int cleared = -1;
  if (const auto early = early_clearances_.find(job_id); early != early_clearances_.end()) {
    cleared = early->second;
  }
  early_clearances_.clear();
  job_ = RunningJob{job_id, std::move(order), cleared, first_action - 1, first_action - 1};
  return job_->order.First(cleared);
}

std::optional<Order> VehicleSession::Clear(const std::string& job_id, int cleared_up_to_action) {
  if (!job_ || job_->job_id != job_id) {
    early_clearances_[job_id] = std::max(early_clearances_[job_id], cleared_up_to_action);
    return std::nullopt;
  }
  job_->cleared_up_to_action = std::max(job_->cleared_up_to_action, cleared_up_to_action);
  return job_->order.Release(job_->cleared_up_to_action);
}

std::optional<Action> VehicleSession::Command(const JobCommand& command,
                                              const std::string& action_id,
                                              std::vector<JobEvent>* events) {
  if (!job_ || command.job_id != job_->job_id) return std::nullopt;
  Action action;
  action.action_id = action_id;
  action.blocking_type = BlockingType::kHard;
  switch (command.type) {
    case JobCommandType::kPause:
      action.action_type = "startPause";
      return action;
    case JobCommandType::kResume:
      action.action_type = "stopPause";
      return action;
    case JobCommandType::kCancel:
      action.action_type = "cancelOrder";
      events->push_back(Event(JobEventType::kCancelled, job_->started_action, command.reason));
      job_.reset();
      return action;
    case JobCommandType::kClearance:
      return std::nullopt;
  }
  return std::nullopt;
}

Telemetry VehicleSession::PositionTelemetry(const std::optional<AgvPosition>& position,
                                            const std::optional<Velocity>& velocity,
                                            int64_t now_ns) {
  if (position) pose_ = Pose2(position->x_m, position->y_m, position->theta_rad);
  Telemetry telemetry;
  telemetry.stamp_ns = now_ns;
  if (pose_) telemetry.pose_in_map = *pose_;
  if (velocity) {
    telemetry.velocity.vx_mps = velocity->vx_mps;
    telemetry.velocity.vy_mps = velocity->vy_mps;
    telemetry.velocity.yaw_rate_radps = velocity->omega_radps;
  }
  const bool localized = position && position->position_initialized;
  telemetry.localization_confidence = localized ? position->localization_score.value_or(1.0) : 0.0;
  telemetry.localization_lost = !localized;
  if (job_) {
    telemetry.job_id = job_->job_id;
    telemetry.action_index = std::max(job_->started_action, job_->finished_action + 1);
  }
  return telemetry;
}

Telemetry VehicleSession::OnVisualization(const Visualization& visualization, int64_t now_ns) {
  return PositionTelemetry(visualization.agv_position, visualization.velocity, now_ns);
}

VehicleSession::Outcome VehicleSession::OnState(const State& state, int64_t now_ns) {
  Outcome out{PositionTelemetry(state.agv_position, state.velocity, now_ns), {}};
  Telemetry& telemetry = out.telemetry;
  telemetry.sequence = state.header.header_id;
  telemetry.mode = state.driving ? NavigationMode::kFreeNavigation : NavigationMode::kIdle;
  telemetry.battery_fraction = std::clamp(state.battery_charge_percent / 100.0, 0.0, 1.0);
  if (!job_) return out;

  RunningJob& job = *job_;
  // The vehicle refused our order, or cannot go on.
  for (const VehicleError& error : state.errors) {
    bool about_ours = state.order_id == job.order.order_id();
    for (const auto& [key, value] : error.references) {
      if (key == "orderId") about_ours = value == job.order.order_id();
    }
    const bool refusal = error.error_type == "validationError" || error.error_type == "orderError";
    if ((refusal && about_ours) || error.level == ErrorLevel::kFatal) {
      out.events.push_back(
          Event(JobEventType::kFailed, std::max(job.started_action, 0),
                absl::StrCat("the vehicle reports ", error.error_type,
                             error.description.empty() ? "" : ": ", error.description)));
      job_.reset();
      return out;
    }
  }
  if (state.order_id != job.order.order_id()) return out;  // not taken yet

  // The last node passed, if it is ours.
  size_t passed = 0;
  const size_t node = JobOrder::NodeIndex(state.last_node_sequence_id);
  if (node < job.order.node_count() && state.last_node_id == job.order.NodeId(node)) passed = node;
  const auto start = [&](int action) {
    if (action > job.started_action && action <= job.cleared_up_to_action) {
      out.events.push_back(Event(JobEventType::kActionStarted, action, ""));
      job.started_action = action;
    }
  };
  for (int action = job.finished_action + 1; action < job.order.action_count(); ++action) {
    if (job.order.EndNodeOf(action) > passed) break;
    if (action > job.started_action) {
      out.events.push_back(Event(JobEventType::kActionStarted, action, ""));
      job.started_action = action;
    }
    out.events.push_back(Event(JobEventType::kActionFinished, action, ""));
    job.finished_action = action;
  }
  if (job.finished_action + 1 >= job.order.action_count()) {
    out.events.push_back(Event(JobEventType::kSucceeded, job.finished_action, ""));
    job_.reset();
    telemetry.job_progress_fraction = 1.0;
    return out;
  }
  if (state.driving) start(job.finished_action + 1);
  telemetry.action_index = std::max(job.started_action, job.finished_action + 1);
  telemetry.job_progress_fraction =
      static_cast<double>(passed) / static_cast<double>(job.order.node_count() - 1);
  return out;
}

}  // namespace fleetnav::vda5050
