#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/job.hpp"
#include "fleetnav/core/job_assignment.hpp"
#include "fleetnav/server/jobs/job_ledger.hpp"
#include "fleetnav/server/site/site_cache.hpp"
#include "fleetnav/server/site/site_catalog.hpp"
#include "fleetnav/server/traffic/traffic_coordinator.hpp"

namespace fleetnav::server {

/// What a robot is sent for a job: the route (a go-to-goal job is a route of one
/// free-navigation action) and the map and marker-set versions to drive it on. NotFound when
/// the route or the map is gone.
absl::StatusOr<JobAssignment> ResolveAssignment(const Job& job, SiteCatalog& site,
                                                SiteCache& site_data);

/// The job services' side of traffic coordination: tells the TrafficCoordinator when jobs
/// begin, resume, advance and end, and stores a WAITING_FOR_TRAFFIC event each time a job's
/// wait changes. Without a coordinator (null) robots are not coordinated and every call does
/// nothing. Not thread-safe: JobService serialises its callers.
class JobTraffic {
 public:
  JobTraffic(TrafficCoordinator* traffic, JobLedger* ledger) : traffic_(traffic), ledger_(ledger) {}

  /// A job begins on `robot_id` from its first action.
  void Begin(const std::string& robot_id, const JobAssignment& assignment);
  /// A job goes on after the robot or the server was away: the robot is sent its clearances
  /// again, or the job is coordinated anew from where the robot reports.
  void Resume(const std::string& robot_id, const JobAssignment& assignment);
  void OnActionFinished(const std::string& robot_id, const std::string& job_id, int action_index);
  void End(const std::string& job_id);
  /// Decides clearances and records each changed wait on its job.
  void Update();
  /// Idle robots found in a waiting robot's way, each with a place to go to (none without a
  /// coordinator).
  std::vector<MakeWayRequest> TakeMakeWayRequests();

 private:
  TrafficCoordinator* traffic_;
  JobLedger* ledger_;
};

}  // namespace fleetnav::server
