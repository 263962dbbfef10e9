#include "fleetnav/server/jobs/job_traffic.hpp"

#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::server {

absl::StatusOr<JobAssignment> ResolveAssignment(const Job& job, SiteCatalog& site,
                                                SiteCache& site_data) {
  JobAssignment assignment;
  assignment.job = job;
  if (!job.route_name.empty()) {
    ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredRoute> route,
                     site.GetRoute(job.route_name, job.route_version));
    assignment.route = std::shared_ptr<const Route>(route, &route->route);
    assignment.route_version = route->version;
  } else if (job.goal) {
    auto goal_route = std::make_shared<Route>();
    goal_route->name = "goal";
    goal_route->map_id = job.map_id;
    FreeNavigationAction go;
    go.goal = *job.goal;
    goal_route->actions.push_back({go, {EndConditionKind::kGoalReached}});
    assignment.route = std::move(goal_route);
  }
  ASSIGN_OR_RETURN(assignment.map_version, site_data.LatestMapVersion(job.map_id));
  assignment.marker_set_version = site_data.LatestMarkerSetVersion(job.map_id);
  assignment.zone_set_version = site.LatestZoneSetVersion(job.map_id);
  return assignment;
}

void JobTraffic::Begin(const std::string& robot_id, const JobAssignment& assignment) {
  if (traffic_ != nullptr) traffic_->Begin(robot_id, assignment);
}

void JobTraffic::Resume(const std::string& robot_id, const JobAssignment& assignment) {
  if (traffic_ == nullptr) return;
  if (traffic_->Tracks(assignment.job.job_id)) {
    traffic_->Resend(robot_id);
  } else {
    traffic_->Begin(robot_id, assignment, TrafficCoordinator::kResumeWhereReported);
  }
}

void JobTraffic::OnActionFinished(const std::string& robot_id, const std::string& job_id,
                                  int action_index) {
  if (traffic_ == nullptr) return;
  traffic_->OnActionFinished(robot_id, job_id, action_index);
  Update();
}

void JobTraffic::End(const std::string& job_id) {
  if (traffic_ != nullptr) traffic_->End(job_id);
}

std::vector<MakeWayRequest> JobTraffic::TakeMakeWayRequests() {
  if (traffic_ == nullptr) return {};
  return traffic_->TakeMakeWayRequests();
}

void JobTraffic::Update() {
  if (traffic_ == nullptr) return;
  for (const TrafficWaitChange& change : traffic_->Update()) {
    if (change.reason.empty()) continue;
    absl::StatusOr<Job> job = ledger_->Get(change.job_id);
    if (!job.ok() || IsTerminal(job->state)) continue;
    (void)ledger_->Record(*job, ledger_->MakeEvent(*job, JobEventType::kWaitingForTraffic,
                                                   change.reason, change.robot_id));
  }
}

}  // namespace fleetnav::server
