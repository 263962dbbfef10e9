#pragma once

#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/job.hpp"
#include "fleetnav/server/jobs/job_ledger.hpp"
#include "fleetnav/server/jobs/job_needs.hpp"
#include "fleetnav/server/jobs/job_recovery.hpp"
#include "fleetnav/server/jobs/job_traffic.hpp"
#include "fleetnav/server/jobs/work_signal.hpp"
#include "fleetnav/server/robots/fleet_registry.hpp"
#include "fleetnav/server/robots/robot_mailbox.hpp"
#include "fleetnav/server/site/goal_reachability.hpp"
#include "fleetnav/server/site/site_cache.hpp"
#include "fleetnav/server/site/site_catalog.hpp"

namespace fleetnav::server {

using ::fleetnav::SubmitJobRequest;

/// A job's life from submission to its end as operators and robots move it: submit (checked
/// against the site before anything is stored), cancel, pause and resume by an operator, and
/// the robot's own reports (actions started and finished, progress, success, failure). Every
/// change is stored with its event before the robot is told; a robot freed wakes the
/// dispatcher. Not thread-safe: JobService serialises its callers.
class JobLifecycle {
 public:
  JobLifecycle(JobLedger* ledger, SiteCatalog* site, SiteCache* site_data, FleetRegistry* registry,
               RobotMailbox* mailbox, JobTraffic* traffic, JobRecovery* recovery, WorkSignal* work)
      : ledger_(ledger),
        site_(site),
        site_data_(site_data),
        reachability_(site_data),
        registry_(registry),
        mailbox_(mailbox),
        traffic_(traffic),
        recovery_(recovery),
        work_(work) {}

  /// Checks the job against the site and, when it names a connected robot, against what that
  /// robot can run (FailedPrecondition naming the robot, its kind and the action), then stores
  /// it; nothing is stored when a check fails. A goal must be on a free cell (InvalidArgument)
  /// where a robot that may run it fits and which it can reach from where it stands
  /// (FailedPrecondition naming the robot; CheckGoalReachable).
  absl::StatusOr<storage::CreatedJob> Submit(const SubmitJobRequest& request);
  /// FailedPrecondition for a job that has already ended.
  absl::StatusOr<Job> Cancel(const std::string& job_id, const std::string& reason);
  /// Takes an assigned job back from its robot before the robot has started it (traffic
  /// coordination: its robot must make way first): the robot is told to drop it and is free,
  /// and the job is queued again with a QUEUED event saying why, keeping its age and priority.
  /// FailedPrecondition unless the job is assigned.
  absl::StatusOr<Job> Withdraw(const std::string& job_id, const std::string& reason);
  /// FailedPrecondition for a job that is neither assigned nor running.
  absl::StatusOr<Job> Pause(const std::string& job_id, const std::string& reason);
  /// FailedPrecondition for a job that is not paused or whose robot is away.
  absl::StatusOr<Job> Resume(const std::string& job_id);
  void OnRobotEvent(const std::string& robot_id, const JobEvent& event);
  void OnTelemetry(const std::string& robot_id, const Telemetry& telemetry);

 private:
  /// FailedPrecondition when `robot` is connected and lacks one of `needs`.
  static absl::Status CheckRobotCanRun(const RobotRecord& robot,
                                       const std::vector<NeededCapability>& needs);
  /// The named robot, or else some robot that runs free navigation, fits at the goal and can
  /// reach it from where it stands (GoalReachability); OK when no such robot is known yet.
  absl::Status CheckGoalReachable(const SubmitJobRequest& request, const storage::StoredMap& map);
  /// A job the server takes back (cancelled or withdrawn): no longer coordinated or awaited,
  /// and its robot, if any, told to drop it and free for the next job.
  void TakeFromRobot(const std::string& job_id, const std::string& robot_id,
                     const std::string& why);
  /// Stores the job's end reported by its robot and frees the robot.
  void End(Job& job, JobState state, const JobEvent& event, const std::string& robot_id);

  JobLedger* ledger_;
  SiteCatalog* site_;
  SiteCache* site_data_;
  GoalReachability reachability_;
  FleetRegistry* registry_;
  RobotMailbox* mailbox_;
  JobTraffic* traffic_;
  JobRecovery* recovery_;
  WorkSignal* work_;
};

}  // namespace fleetnav::server
