#include "fleetnav/server/jobs/job_matcher.hpp"

#include <algorithm>
#include <limits>

#include "absl/strings/str_cat.h"

namespace fleetnav::server {
namespace {

/// Added to the straight-line distance of a robot with no path to a job's start: it is
/// considered only when no robot has one.
constexpr double kNoPathRankM = 1e6;

bool Fits(const std::vector<std::string>& have, const std::vector<std::string>& needed) {
  return std::all_of(needed.begin(), needed.end(), [&](const std::string& c) {
    return std::find(have.begin(), have.end(), c) != have.end();
  });
}

/// What a queued job asks for: a robot by id (empty: any) with these capabilities.
using Demand = std::pair<std::string, const std::vector<std::string>*>;

bool SameDemand(const Demand& a, const Demand& b) {
  return a.first == b.first && *a.second == *b.second;
}

}  // namespace

void JobMatcher::OnJobSucceeded(const std::string& robot_id, const std::string& job_id) {
  // Another job of the robot succeeded: a make-way job of it that failed no longer keeps it
  // from being sent again. One still to run stays known as a make-way job (forgotten, it was
  // withdrawn as an ordinary job, given again and withdrawn again ten times a second).
  if (auto made_way = make_way_job_.find(robot_id);
      made_way != make_way_job_.end() && made_way->second != job_id) {
    absl::StatusOr<Job> job = ledger_->Get(made_way->second);
    if (!job.ok() || IsTerminal(job->state)) make_way_job_.erase(made_way);
  }
}

void JobMatcher::ForgetRobot(const std::string& robot_id) {
  robot_map_.erase(robot_id);
  charging_job_.erase(robot_id);
  make_way_job_.erase(robot_id);
}

JobMatcher::RouteFacts JobMatcher::RouteFacts::Of(std::vector<NeededCapability> needs,
                                                  std::optional<Eigen::Vector2d> start) {
  RouteFacts facts;
  for (const NeededCapability& need : needs) facts.needed.push_back(need.capability);
  std::sort(facts.needed.begin(), facts.needed.end());
  facts.needs = std::move(needs);
  facts.start = start;
  return facts;
}

JobMatcher::RouteFacts JobMatcher::FactsOf(const Job& job) {
  if (job.goal) return RouteFacts::Of(NeedsOfGoal(), job.goal->translation());
  const auto key = std::make_pair(job.route_name, job.route_version);
  auto known = route_facts_.find(key);
  if (known != route_facts_.end()) return known->second;
  RouteFacts facts;
  absl::StatusOr<std::shared_ptr<const storage::StoredRoute>> route =
      site_->GetRoute(job.route_name, job.route_version);
  if (route.ok()) {
    std::optional<Eigen::Vector2d> start;
    for (const RouteAction& action : (*route)->route.actions) {
      const auto* nav = std::get_if<FreeNavigationAction>(&action.params);
      if (nav != nullptr && !start) {
        start = nav->waypoints_m.empty() ? nav->goal.translation() : nav->waypoints_m.front();
      }
    }
    facts = RouteFacts::Of(NeedsOfRoute((*route)->route), start);
  }
  return route_facts_.emplace(key, std::move(facts)).first->second;
}

void JobMatcher::SayWhyQueued(Job& job, const std::vector<NeededCapability>& needs,
                              const FleetCapabilities& fleet) {
  std::string why;
  if (!job.requested_robot_id.empty()) {
    const std::string& id = job.requested_robot_id;
    absl::StatusOr<RobotRecord> robot = registry_->Get(id);
    if (!robot.ok()) {
      why = absl::StrCat("robot ", id, " is not known");
    } else if (robot->connection != ConnectionState::kOnline) {
      why = absl::StrCat(
          "robot ", id, " is ",
          robot->connection == ConnectionState::kStale ? "not reporting (stale)" : "offline");
    } else {
      const auto& have = robot->identity.capabilities;
      if (const std::optional<NeededCapability> unmet =
              FirstUnmet(needs, [&](const std::string& capability) {
                return std::find(have.begin(), have.end(), capability) != have.end();
              })) {
        why = absl::StrCat("robot ", id, " (", robot->identity.model.kind_name, ") cannot run ",
                           unmet->Describe());
      }
      if (why.empty() && !robot->current_job_id.empty()) {
        why = absl::StrCat("waits for robot ", id, " to finish job ", robot->current_job_id);
      } else if (why.empty()) {
        why = absl::StrCat("robot ", id,
                           charging_job_.contains(id) ? " is kept for charging" : " is not free");
      }
    }
  } else {
    const auto in = [](const std::set<std::string>& set) {
      return [&set](const std::string& capability) { return set.contains(capability); };
    };
    if (const std::optional<NeededCapability> never = FirstUnmet(needs, in(fleet.known))) {
      why = absl::StrCat("no robot that has connected can run ", never->Describe());
    } else if (const std::optional<NeededCapability> away = FirstUnmet(needs, in(fleet.online))) {
      why = absl::StrCat("no connected robot can run ", away->Describe());
    }
    if (why.empty()) why = "every connected robot that can run it is busy or charging";
  }
  if (why == job.reason) return;
  job.reason = why;
  (void)ledger_->Record(job, ledger_->MakeEvent(job, JobEventType::kQueued, why, ""));
}

bool JobMatcher::HeldForCharging(const RobotRecord& robot) {
  auto it = charging_job_.find(robot.identity.robot_id);
  if (it == charging_job_.end()) return false;
  absl::StatusOr<Job> job = ledger_->Get(it->second);
  const bool charged =
      robot.last_telemetry && robot.last_telemetry->battery_fraction >= params_.charged_fraction;
  if (!job.ok() || job->state == JobState::kFailed || job->state == JobState::kCancelled ||
      (job->state == JobState::kSucceeded && charged)) {
    charging_job_.erase(it);  // charged, or sent again on the next pass
    return false;
  }
  return true;
}

void JobMatcher::SendLowRobotsToCharge() {
  if (params_.charge_below_fraction <= 0.0 || params_.charging_routes.empty()) return;
  const std::vector<RobotRecord> low = registry_->IdleOnline([&](const RobotRecord& r) {
    return r.last_telemetry && r.last_telemetry->battery_fraction < params_.charge_below_fraction;
  });
  for (const RobotRecord& robot : low) {
    if (HeldForCharging(robot)) continue;
    const std::string& id = robot.identity.robot_id;
    std::string route;
    if (auto map = robot_map_.find(id); map != robot_map_.end()) {
      if (auto r = params_.charging_routes.find(map->second); r != params_.charging_routes.end()) {
        route = r->second;
      }
    } else if (params_.charging_routes.size() == 1) {
      route = params_.charging_routes.begin()->second;
    }
    if (route.empty()) continue;  // no charger known for where it is
    SubmitJobRequest request;
    request.route_name = route;
    request.robot_id = id;
    request.priority = std::numeric_limits<int>::max();
    request.idempotency_key = absl::StrCat("charge/", id, "/", ledger_->NowUnixMs());
    absl::StatusOr<storage::CreatedJob> created = lifecycle_->Submit(request);
    if (created.ok()) charging_job_[id] = created->job.job_id;
  }
}

bool JobMatcher::WouldSendToMakeWay(const MakeWayRequest& request,
                                    const std::string& ending_job_id) const {
  // Traffic coordination counts idle robots as obstacles by coordinates on every map; a robot
  // whose last job was on another map stands on another site and is not sent here.
  if (auto map = robot_map_.find(request.robot_id);
      map != robot_map_.end() && map->second != request.map_id) {
    return false;
  }
  auto pending = make_way_job_.find(request.robot_id);
  if (pending == make_way_job_.end() || pending->second == ending_job_id) return true;
  // Not while its make-way job runs; nor when it failed (its bumper, a plan it could not make)
  // until another of its jobs has succeeded: asking again would only fail again.
  absl::StatusOr<Job> job = ledger_->Get(pending->second);
  return !job.ok() || (IsTerminal(job->state) && job->state != JobState::kFailed);
}

void JobMatcher::SendToMakeWay(const std::vector<MakeWayRequest>& requests) {
  for (const MakeWayRequest& request : requests) {
    if (!WouldSendToMakeWay(request, "")) continue;
    make_way_job_.erase(request.robot_id);  // one that ended
    SubmitJobRequest submit;
    submit.goal_map_id = request.map_id;
    submit.goal = request.place;
    submit.robot_id = request.robot_id;
    submit.priority = std::numeric_limits<int>::max();
    submit.idempotency_key = absl::StrCat("make-way/", request.robot_id, "/", ledger_->NowUnixMs());
    absl::StatusOr<storage::CreatedJob> created = lifecycle_->Submit(submit);
    if (created.ok()) make_way_job_[request.robot_id] = created->job.job_id;
  }
}

bool JobMatcher::IsMakeWayJob(const std::string& job_id) const {
  return std::any_of(make_way_job_.begin(), make_way_job_.end(),
                     [&](const auto& entry) { return entry.second == job_id; });
}

std::vector<RobotRecord>::iterator JobMatcher::Nearest(std::vector<RobotRecord>& idle,
                                                       const Job& job, const RouteFacts& facts) {
  auto best = idle.end();
  double best_distance_m = std::numeric_limits<double>::infinity();
  for (auto it = idle.begin(); it != idle.end(); ++it) {
    if (!job.requested_robot_id.empty() && it->identity.robot_id != job.requested_robot_id) {
      continue;
    }
    if (!Fits(it->identity.capabilities, facts.needed)) continue;
    // A robot kept for charging takes its charging job only.
    if (HeldForCharging(*it) && charging_job_.at(it->identity.robot_id) != job.job_id) continue;
    double distance_m = 0.0;
    if (facts.start && it->last_telemetry) {
      const Eigen::Vector2d here = it->last_telemetry->pose_in_map.translation();
      const std::optional<double> path_m = travel_.Between(job.map_id, here, *facts.start);
      // No path known (off the map, walled off): ranked after every robot with one.
      distance_m = path_m ? *path_m : kNoPathRankM + (here - *facts.start).norm();
    }
    if (distance_m < best_distance_m) {
      best_distance_m = distance_m;
      best = it;
    }
  }
  return best;
}

bool JobMatcher::Assign(Job& job, const std::string& robot_id) {
  job.assigned_robot_id = robot_id;
  job.reason.clear();  // why it was queued no longer holds (Job.reason: why it failed or ended)
  robot_map_[robot_id] = job.map_id;
  if (!ledger_->Transition(job, JobState::kAssigned, JobEventType::kAssigned, "", robot_id).ok()) {
    return false;
  }
  absl::StatusOr<JobAssignment> assignment = ResolveAssignment(job, *site_, *site_data_);
  if (!assignment.ok() || !mailbox_->SendAssignment(robot_id, *assignment)) {
    job.assigned_robot_id.clear();
    (void)ledger_->Transition(job, JobState::kQueued, JobEventType::kQueued,
                              assignment.ok() ? "robot unreachable; re-queued"
                                              : std::string(assignment.status().message()),
                              robot_id);
    return false;
  }
  registry_->SetCurrentJob(robot_id, job.job_id);
  traffic_->Begin(robot_id, *assignment);
  return true;
}

int JobMatcher::AssignQueued() {
  storage::JobFilter queued_filter;
  queued_filter.states = {JobState::kQueued};
  queued_filter.page_size = params_.max_page_size;
  absl::StatusOr<storage::JobPage> page = ledger_->List(queued_filter);
  if (!page.ok() || page->jobs.empty()) return 0;
  std::vector<Job> queued = page->jobs;
  std::stable_sort(queued.begin(), queued.end(), [](const Job& a, const Job& b) {
    return a.priority != b.priority ? a.priority > b.priority
                                    : a.created_unix_ms < b.created_unix_ms;
  });
  std::vector<RouteFacts> job_facts;
  job_facts.reserve(queued.size());
  for (const Job& job : queued) job_facts.push_back(FactsOf(job));
  // Only robots that can serve one of the queued jobs' demands are copied out of the registry,
  // so jobs no robot can drive cost nothing per robot, however large the fleet.
  std::vector<Demand> demands;
  for (size_t j = 0; j < queued.size(); ++j) {
    Demand demand{queued[j].requested_robot_id, &job_facts[j].needed};
    const bool seen = std::any_of(demands.begin(), demands.end(),
                                  [&](const Demand& d) { return SameDemand(d, demand); });
    if (!seen) demands.push_back(demand);
  }
  std::vector<RobotRecord> idle = registry_->IdleOnline([&](const RobotRecord& record) {
    return std::any_of(demands.begin(), demands.end(), [&](const Demand& d) {
      return (d.first.empty() || d.first == record.identity.robot_id) &&
             Fits(record.identity.capabilities, *d.second);
    });
  });
  // A demand that found no robot finds none later in this pass either: idle robots only leave.
  std::vector<Demand> unmet;
  std::optional<FleetCapabilities> fleet;  // read once, when a job waits
  int assigned = 0;
  for (size_t j = 0; j < queued.size(); ++j) {
    Job& job = queued[j];
    const Demand demand{job.requested_robot_id, &job_facts[j].needed};
    const bool known_unmet = std::any_of(unmet.begin(), unmet.end(),
                                         [&](const Demand& d) { return SameDemand(d, demand); });
    auto best = known_unmet || idle.empty() ? idle.end() : Nearest(idle, job, job_facts[j]);
    if (best == idle.end()) {
      if (!known_unmet && !idle.empty()) unmet.push_back(demand);
      if (!fleet) {
        fleet = FleetCapabilities{registry_->OnlineCapabilities(), registry_->KnownCapabilities()};
      }
      SayWhyQueued(job, job_facts[j].needs, *fleet);
      continue;
    }
    if (!Assign(job, best->identity.robot_id)) continue;
    idle.erase(best);
    ++assigned;
  }
  return assigned;
}

}  // namespace fleetnav::server
