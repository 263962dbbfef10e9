#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "fleetnav/core/job.hpp"
#include "fleetnav/core/job_assignment.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/vda5050/job_order.hpp"
#include "fleetnav/vda5050/vda_messages.hpp"

namespace fleetnav::vda5050 {

/// What one VDA vehicle's messages mean for fleetnav, with no network: the job it runs as an
/// order, how far traffic coordination lets it go, and, from each `state`, the robot's
/// telemetry and the job events a fleetnav agent would report — an action started when the
/// vehicle sets off on it, finished when it passes the action's end node (so robots waiting for
/// it may go), the job succeeded when the last one is passed, and failed when the vehicle
/// refuses the order (validationError, orderError, §6.6.4) or reports a FATAL error. Messages
/// whose header id does not grow per topic (§6.4) are stale and left out. Not thread-safe.
class VehicleSession {
 public:
  explicit VehicleSession(std::string robot_id) : robot_id_(std::move(robot_id)) {}

  /// False for a message of `topic` whose header id is not above the last one seen (a resend
  /// or out of order), which the caller ignores. A header id of 0 after a higher one is taken
  /// as the vehicle restarting its counter.
  bool Fresh(const std::string& topic, uint32_t header_id);
  /// Forgets the header ids seen (the vehicle connected anew and counts from 0 again).
  void ResetHeaders() { last_header_ids_.clear(); }

  /// Starts `job_id` as `order` from action `first_action` (> 0 for a job resumed after the
  /// robot came back); returns the first order message, with what is cleared so far.
  Order Start(const std::string& job_id, JobOrder order, int first_action = 0);
  /// A traffic clearance: an order update when it lets the vehicle go further, else nullopt.
  /// A clearance for a job not started yet is kept for its start.
  std::optional<Order> Clear(const std::string& job_id, int cleared_up_to_action);
  /// The instant action (§6.8) for a pause, resume or cancel of the current job: startPause,
  /// stopPause, cancelOrder (a cancel also ends the job here and reports it cancelled). nullopt
  /// for another job or a clearance.
  std::optional<Action> Command(const JobCommand& command, const std::string& action_id,
                                std::vector<JobEvent>* events);

  struct Outcome {
    Telemetry telemetry;
    std::vector<JobEvent> events;
  };
  Outcome OnState(const State& state, int64_t now_ns);
  /// A visualization message: the pose in between states (§6.13), as telemetry.
  Telemetry OnVisualization(const Visualization& visualization, int64_t now_ns);

  const std::string& robot_id() const { return robot_id_; }
  /// The current job ("" when idle).
  std::string job_id() const { return job_ ? job_->job_id : ""; }
  const JobOrder* order() const { return job_ ? &job_->order : nullptr; }
  /// The vehicle's pose from its last state with a position.
  const std::optional<Pose2>& pose() const { return pose_; }

 private:
  struct RunningJob {
    std::string job_id;
    JobOrder order;
    int cleared_up_to_action = -1;
    int started_action = -1;   ///< the latest action reported started
    int finished_action = -1;  ///< the latest action reported finished
  };
  JobEvent Event(JobEventType type, int action_index, const std::string& reason) const;
  /// Takes the position (if any) as the vehicle's pose; telemetry with the pose, velocity,
  /// localization and the job's current action.
  Telemetry PositionTelemetry(const std::optional<AgvPosition>& position,
                              const std::optional<Velocity>& velocity, int64_t now_ns);

  std::string robot_id_;
  std::map<std::string, uint32_t> last_header_ids_;
  std::optional<RunningJob> job_;
  std::map<std::string, int> early_clearances_;  ///< clearances before their job's start
  std::optional<Pose2> pose_;
};

}  // namespace fleetnav::vda5050
