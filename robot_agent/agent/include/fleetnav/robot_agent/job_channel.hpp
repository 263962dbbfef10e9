#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fleetnav/core/job.hpp"
#include "fleetnav/core/job_assignment.hpp"

namespace fleetnav::agent {

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
