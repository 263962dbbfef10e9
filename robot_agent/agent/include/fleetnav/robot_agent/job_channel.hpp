#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fleetnav/core/job.hpp"
#include "fleetnav/core/route.hpp"

namespace fleetnav::agent {

/// A job as the agent receives it from the server.
struct JobAssignment {
  Job job;
  Route route;
  /// The map and versions the route was validated against ("" / 0: unknown, use what the
  /// agent has).
  std::string map_id;
  uint32_t map_version = 0;
  uint32_t marker_set_version = 0;
  /// Where to begin: the route's beginning, or — for a job the robot held before its agent
  /// restarted — the action it was in and how much of it was done.
  RoutePosition resume;
};

/// kClearance: traffic coordination lets the robot start the job's actions up to
/// cleared_up_to_action (-1 after a reconnect: nothing beyond the action it is in until the
/// server says again).
enum class JobCommandType { kPause, kResume, kCancel, kClearance };

struct JobCommand {
  JobCommandType type = JobCommandType::kCancel;
  std::string job_id;
  std::string reason;
  int cleared_up_to_action = -1;
};

/// The agent's side of job dispatch: assignments and commands in, job events out. The server
/// link implements it; tests use a fake. Never blocks the control loop.
class JobChannel {
 public:
  virtual ~JobChannel() = default;
  virtual std::optional<JobAssignment> TakeAssignment() = 0;
  virtual std::vector<JobCommand> TakeCommands() = 0;
  /// Reports an event of the current job; events are delivered in order and never dropped.
  virtual void ReportEvent(const JobEvent& event) = 0;
  /// The job the robot is executing, announced again on every reconnect ("" when idle).
  virtual void SetCurrentJob(const std::string& job_id) = 0;
};

}  // namespace fleetnav::agent
