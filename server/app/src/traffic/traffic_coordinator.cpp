#include "fleetnav/server/traffic/traffic_coordinator.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/segment_gate.hpp"
#include "fleetnav/planner/coordination/make_way.hpp"
#include "fleetnav/planner/coordination/route_segments.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"

namespace fleetnav::server {
namespace {

/// Whether a robot keeps to its predicted path closely enough to follow another a segment
/// behind: it localizes with a laser against the map (the Lely's estimate drifts by up to half
/// a metre between markers) and does not steer by Ackermann (its pure pursuit cut a corner to
/// 6 cm of a passing platform in the store fleet).
bool FollowsClosely(const RobotModel& model) {
  const bool laser_localized =
      std::any_of(model.sensors.begin(), model.sensors.end(),
                  [](const SensorMount& sensor) { return sensor.type == SensorType::kLaser; });
  return laser_localized && model.kinematics != Kinematics::kAckermann;
}

}  // namespace

absl::Status TrafficCoordinatorParams::Validate() const {
  if (!std::isfinite(margin_m) || margin_m < 0.0) {
    return absl::InvalidArgumentError(absl::StrCat("margin_m: must be >= 0, got ", margin_m));
  }
  if (!std::isfinite(cell_m) || cell_m <= 0.0) {
    return absl::InvalidArgumentError(absl::StrCat("cell_m: must be > 0, got ", cell_m));
  }
  if (!std::isfinite(standing_margin_min_m) || standing_margin_min_m < 0.0 ||
      standing_margin_min_m > margin_m || !std::isfinite(standing_sigmas) ||
      standing_sigmas < 0.0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "standing_margin_min_m must be in [0, margin_m] and standing_sigmas >= 0, got ",
        standing_margin_min_m, " and ", standing_sigmas));
  }
  if (!std::isfinite(segment_m) || segment_m < 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("segment_m: must be >= 0 (0: whole actions), got ", segment_m));
  }
  if (!std::isfinite(recheck_period_s) || recheck_period_s < 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("recheck_period_s: must be >= 0, got ", recheck_period_s));
  }
  if (absl::Status s = make_way.Validate(); !s.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("make_way.", s.message()));
  }
  if (horizon_actions < 2) {
    return absl::InvalidArgumentError(
        absl::StrCat("horizon_actions: must be >= 2, got ", horizon_actions));
  }
  return absl::OkStatus();
}

TrafficCoordinator::TrafficCoordinator(SiteCache* site_data, FleetRegistry* registry,
                                       RobotMailbox* mailbox, const Clock* clock,
                                       TrafficCoordinatorParams params)
    : site_data_(site_data),
      registry_(registry),
      mailbox_(mailbox),
      clock_(clock),
      params_(params) {}

void TrafficCoordinator::Begin(const std::string& robot_id, const JobAssignment& assignment,
                               int resume_action) {
  absl::StatusOr<RobotRecord> record = registry_->Get(robot_id);
  absl::MutexLock lock(&mutex_);
  Tracked tracked;
  tracked.robot_id = robot_id;
  tracked.assignment = assignment;
  if (record.ok()) {
    tracked.model = record->identity.model;
    tracked.segment_clearances = record->identity.segment_clearances;
  }
  tracked.assigned_s = static_cast<double>(clock_->NowNs()) * 1e-9;
  tracked.start_action = std::max(resume_action, 0);
  tracked.resume_from_telemetry = resume_action == kResumeWhereReported;
  jobs_[assignment.job.job_id] = std::move(tracked);
  make_way_asked_.erase(robot_id);
  cannot_make_way_.erase(robot_id);
  changed_ = true;
}

bool TrafficCoordinator::Tracks(const std::string& job_id) {
  absl::MutexLock lock(&mutex_);
  return jobs_.count(job_id) > 0;
}

void TrafficCoordinator::OnActionFinished(const std::string& robot_id, const std::string& job_id,
                                          int action_index) {
  absl::MutexLock lock(&mutex_);
  auto it = jobs_.find(job_id);
  if (it == jobs_.end() || it->second.robot_id != robot_id) return;
  Tracked& tracked = it->second;
  tracked.start_action = std::max(tracked.start_action, action_index + 1);
  changed_ = true;
  if (tracked.schedule) {
    tracked.schedule->first_unfinished =
        std::max(tracked.schedule->first_unfinished, FirstStepOf(tracked, action_index + 1));
    const int first_unfinished_action =
        tracked.schedule->first_unfinished < static_cast<int>(tracked.steps.size())
            ? tracked.steps[tracked.schedule->first_unfinished].action
            : tracked.predicted_end;
    const bool more =
        tracked.predicted_end < static_cast<int>(tracked.assignment.route->actions.size());
    if (more && first_unfinished_action + params_.horizon_actions / 2 >= tracked.predicted_end) {
      // The next window is predicted on the next update, from where the robot then is.
      tracked.start_action = first_unfinished_action;
      tracked.schedule.reset();
      tracked.assigned_s = static_cast<double>(clock_->NowNs()) * 1e-9;
    }
  }
}

void TrafficCoordinator::End(const std::string& job_id) {
  std::string robot_id;
  {
    absl::MutexLock lock(&mutex_);
    auto it = jobs_.find(job_id);
    if (it == jobs_.end()) return;
    robot_id = it->second.robot_id;
    jobs_.erase(it);
    changed_ = true;
    // The floor a job needed is free again: a robot that found no place to make way to looks
    // again on the next update.
    for (const auto& [stuck_robot_id, why] : cannot_make_way_) {
      make_way_asked_.erase(stuck_robot_id);
    }
  }
  registry_->SetTrafficWait(robot_id, "");
}

void TrafficCoordinator::Resend(const std::string& robot_id) {
  absl::MutexLock lock(&mutex_);
  for (auto& [job_id, tracked] : jobs_) {
    if (tracked.robot_id == robot_id) {
      tracked.sent_cleared = -2;
      changed_ = true;
    }
  }
}

TrafficCoordinator::PlannerCache& TrafficCoordinator::CacheFor(const std::string& map_id,
                                                               uint32_t map_version,
                                                               const RobotModel& model) {
  const auto key = std::make_tuple(map_id, map_version, model.kind_name);
  auto it = planners_.find(key);
  if (it == planners_.end()) {
    PlannerCache cache;
    absl::StatusOr<std::shared_ptr<const storage::StoredMap>> shared =
        site_data_->Map(map_id, map_version);
    if (shared.ok()) {
      const storage::StoredMap* map = shared->get();
      // The agent's free navigation plans with 0.1 m of padding (FreeNavigationParams).
      planner::CostmapParams costmap_params;
      costmap_params.padding_m = 0.1;
      absl::StatusOr<planner::Costmap> costmap =
          planner::Costmap::Build(map->grid, model.footprint_m, costmap_params);
      if (costmap.ok()) {
        cache.costmap = std::make_unique<planner::Costmap>(*std::move(costmap));
        // The planner the robot's agent navigates with, so the prediction is its path.
        const planner::SingleRobotPlannerParams planner_params =
            planner::NavigationPlannerParams(model);
        absl::StatusOr<std::unique_ptr<planner::SingleRobotPlanner>> planner =
            planner::MakeSingleRobotPlanner(cache.costmap.get(), model, planner_params);
        if (planner.ok()) cache.planner = *std::move(planner);
      }
      cache.map_origin = map->grid.origin();
    }
    it = planners_.emplace(key, std::move(cache)).first;
  }
  return it->second;
}

planner::SingleRobotPlanner* TrafficCoordinator::PlannerFor(const Tracked& tracked,
                                                            Pose2* map_origin) {
  PlannerCache& cache =
      CacheFor(tracked.assignment.job.map_id, tracked.assignment.map_version, tracked.model);
  *map_origin = cache.map_origin;
  return cache.planner.get();
}

double TrafficCoordinator::StandingMarginM(const Telemetry& telemetry) const {
  const double variance_m2 = std::max(telemetry.covariance[0], telemetry.covariance[4]);
  if (!std::isfinite(variance_m2) || variance_m2 < 0.0) return params_.margin_m;
  return std::clamp(params_.standing_sigmas * std::sqrt(variance_m2), params_.standing_margin_min_m,
                    params_.margin_m);
}

void TrafficCoordinator::Predict(Tracked& tracked, const Pose2& pose,
                                 const std::optional<Eigen::Vector2d>& carried_load_m,
                                 double standing_margin_m) {
  std::shared_ptr<const storage::StoredMarkerSet> markers;
  if (tracked.assignment.marker_set_version > 0) {
    absl::StatusOr<std::shared_ptr<const storage::StoredMarkerSet>> stored =
        site_data_->MarkerSetVersion(tracked.assignment.job.map_id,
                                     tracked.assignment.marker_set_version);
    if (stored.ok()) markers = *std::move(stored);
  }
  // Only the window of actions ahead is predicted (horizon_actions).
  const std::vector<RouteAction>& all = tracked.assignment.route->actions;
  const int skipped = std::min<int>(tracked.start_action, all.size());
  const int end = std::min<int>(all.size(), skipped + params_.horizon_actions);
  Route remaining;
  remaining.name = tracked.assignment.route->name;
  remaining.map_id = tracked.assignment.route->map_id;
  remaining.actions.assign(all.begin() + skipped, all.begin() + end);
  tracked.predicted_end = end;
  Pose2 map_origin;
  planner::SingleRobotPlanner* planner = PlannerFor(tracked, &map_origin);
  const MarkerSet* marker_set = markers ? &markers->markers : nullptr;
  absl::StatusOr<std::vector<planner::PredictedAction>> predicted =
      planner::PredictRoute(remaining, pose, marker_set, planner, map_origin, params_.prediction);
  if (!predicted.ok() && planner != nullptr) {
    // The agent will say why it cannot plan; the straight lines still reserve its way there.
    predicted =
        planner::PredictRoute(remaining, pose, marker_set, nullptr, map_origin, params_.prediction);
  }
  planner::ScheduledRoute schedule;
  schedule.robot_id = tracked.robot_id;
  schedule.job_id = tracked.assignment.job.job_id;
  // A robot carrying a trolley sweeps the trolley's outline too (RobotModel::CarryingLoad); the
  // load changes where a trolley dock or an undock ends.
  const auto sweep = [&](const std::vector<Pose2>& poses,
                         const std::optional<Eigen::Vector2d>& load_m) {
    return planner::CellSet::Sweep(poses, tracked.model.FootprintCarrying(load_m), params_.margin_m,
                                   params_.cell_m);
  };
  const auto stand = [&](const Pose2& at, const std::optional<Eigen::Vector2d>& load_m) {
    return planner::CellSet::Sweep({at}, tracked.model.FootprintCarrying(load_m), standing_margin_m,
                                   params_.cell_m);
  };
  std::optional<Eigen::Vector2d> load_m = carried_load_m;
  schedule.start_cells = stand(pose, load_m);
  schedule.cells_id = next_cells_id_++;
  // Actions already run are one empty step each.
  tracked.steps.clear();
  for (int k = 0; k < skipped; ++k) {
    tracked.steps.push_back({k, 0, 1, std::nullopt});
    schedule.whole_from.push_back(k);
    schedule.action_cells.emplace_back();
    schedule.action_end_cells.push_back(schedule.start_cells);
    schedule.action_start_s.push_back(tracked.assigned_s);
  }
  const double segment_m =
      tracked.segment_clearances && FollowsClosely(tracked.model) ? params_.segment_m : 0.0;
  double t_s = tracked.assigned_s;
  for (size_t i = 0; i < remaining.actions.size(); ++i) {
    const int action = skipped + static_cast<int>(i);
    if (!predicted.ok()) {
      // Unpredictable (a stripe the marker set lacks): reserve where it stands.
      schedule.whole_from.push_back(static_cast<int>(tracked.steps.size()));
      tracked.steps.push_back({action, 0, 1, std::nullopt});
      schedule.action_cells.push_back(sweep({pose}, carried_load_m));
      schedule.action_end_cells.push_back(schedule.start_cells);
      schedule.action_start_s.push_back(t_s);
      continue;
    }
    const std::optional<Eigen::Vector2d> load_after_m =
        CarriedLoadAfter(remaining.actions[i], load_m, marker_set, Eigen::Vector2d::Zero());
    const bool free_navigation =
        std::holds_alternative<FreeNavigationAction>(remaining.actions[i].params);
    const std::vector<planner::ActionSegment> segments =
        planner::SplitIntoSegments(predicted->at(i), free_navigation ? segment_m : 0.0);
    const int action_first_step = static_cast<int>(tracked.steps.size());
    for (size_t j = 0; j < segments.size(); ++j) {
      const bool last = j + 1 == segments.size();
      schedule.whole_from.push_back(action_first_step);
      tracked.steps.push_back(
          {action, static_cast<int>(j), static_cast<int>(segments.size()), segments[j].gate});
      schedule.action_cells.push_back(sweep(segments[j].poses, load_m));
      // The load changes where the action ends (a trolley dock or an undock).
      schedule.action_end_cells.push_back(
          stand(segments[j].poses.back(), last ? load_after_m : load_m));
      schedule.action_start_s.push_back(t_s);
      t_s += segments[j].duration_s;
    }
    load_m = load_after_m;
  }
  schedule.first_unfinished = skipped;
  // The action the robot may be in already (a later window, or a job resumed after a restart)
  // stays cleared whole.
  if (skipped >= static_cast<int>(tracked.assignment.route->actions.size())) {
    schedule.cleared_up_to = skipped - 1;
  } else if (skipped > 0 || tracked.resume_from_telemetry) {
    schedule.cleared_up_to = FirstStepOf(tracked, skipped + 1) - 1;
  } else {
    schedule.cleared_up_to = -1;
  }
  tracked.schedule = std::move(schedule);
}

namespace {

/// "action 3 (free_navigation)", or "segment 2 of 5 of action 3 (free_navigation)" when the
/// segment is not the action's last.
std::string StepName(int action, int segment, int segments, const Route& route) {
  std::string name = absl::StrCat("action ", action);
  if (action < static_cast<int>(route.actions.size())) {
    absl::StrAppend(&name, " (", std::string(ActionTypeName(route.actions[action].params)), ")");
  }
  if (segment + 1 < segments) {
    name = absl::StrCat("segment ", segment + 1, " of ", segments, " of ", name);
  }
  return name;
}

}  // namespace

int TrafficCoordinator::FirstStepOf(const Tracked& tracked, int action) {
  const auto it = std::lower_bound(tracked.steps.begin(), tracked.steps.end(), action,
                                   [](const Step& step, int a) { return step.action < a; });
  return static_cast<int>(it - tracked.steps.begin());
}

int TrafficCoordinator::ActionOfStep(const Tracked& tracked, int step) {
  return step >= 0 && step < static_cast<int>(tracked.steps.size()) ? tracked.steps[step].action
                                                                    : step;
}

std::string TrafficCoordinator::Describe(const planner::TrafficClearanceDecision& d,
                                         const std::map<std::string, const Tracked*>& jobs_on_map) {
  if (d.waits.empty()) return "";
  const planner::TrafficWait& wait = d.waits.front();
  auto waiting = jobs_on_map.find(d.robot_id);
  const int action =
      waiting != jobs_on_map.end() ? ActionOfStep(*waiting->second, wait.action) : wait.action;
  std::string blocker_step = "its last action";
  auto blocker = jobs_on_map.find(wait.blocker_robot_id);
  if (blocker != jobs_on_map.end() && wait.blocker_action >= 0 &&
      wait.blocker_action < static_cast<int>(blocker->second->steps.size())) {
    const Step& step = blocker->second->steps[wait.blocker_action];
    blocker_step =
        StepName(step.action, step.segment, step.segments, *blocker->second->assignment.route);
  }
  const std::string next = absl::StrCat("action ", action, " waits for ");
  if (d.deadlocked) {
    return absl::StrCat(next, wait.blocker_robot_id,
                        ": the routes block each other; it runs when that job ends");
  }
  if (wait.blocker_action < 0) {
    return absl::StrCat(next, wait.blocker_robot_id, ", which stands in its way");
  }
  return absl::StrCat(next, wait.blocker_robot_id, " to finish ", blocker_step);
}

ClearanceNotice TrafficCoordinator::Notice(const Tracked& tracked,
                                           const planner::TrafficClearanceDecision& d,
                                           const std::map<std::string, const Tracked*>& jobs_on_map,
                                           const std::string& reason) {
  ClearanceNotice notice{tracked.assignment.job.job_id, -1, {}, reason, std::nullopt};
  if (d.cleared_up_to >= 0 && d.cleared_up_to < static_cast<int>(tracked.steps.size())) {
    const Step& step = tracked.steps[d.cleared_up_to];
    notice.cleared_up_to_action = step.action;
    if (step.gate) notice.hold = SegmentHold{step.action, step.segment, *step.gate};
  }
  for (const planner::TrafficWait& wait : d.waits) {
    int blocker_action = wait.blocker_action;
    auto blocker = jobs_on_map.find(wait.blocker_robot_id);
    if (blocker != jobs_on_map.end()) {
      blocker_action = ActionOfStep(*blocker->second, wait.blocker_action);
    }
    notice.waits.push_back(
        {wait.blocker_robot_id, blocker_action, wait.robot_id, ActionOfStep(tracked, wait.action)});
  }
  return notice;
}

void TrafficCoordinator::PassGates(Tracked& tracked, const Telemetry& telemetry) {
  if (!tracked.schedule || telemetry.job_id != tracked.assignment.job.job_id) return;
  int& first = tracked.schedule->first_unfinished;
  while (first < static_cast<int>(tracked.steps.size()) &&
         tracked.steps[first].action == telemetry.action_index && tracked.steps[first].gate &&
         ReachedGate(*tracked.steps[first].gate, telemetry.pose_in_map.translation())) {
    ++first;
  }
}

std::vector<TrafficWaitChange> TrafficCoordinator::Update() {
  {
    // The dispatcher calls this on every pass: with no job there is nothing to order, and the
    // fleet is not copied or swept.
    absl::MutexLock lock(&mutex_);
    if (jobs_.empty()) return {};
    const double now_s = static_cast<double>(clock_->NowNs()) * 1e-9;
    if (!changed_ && now_s - last_decision_s_ < params_.recheck_period_s) return {};
    changed_ = false;
    last_decision_s_ = now_s;
  }
  // Who stands where: online robots without a coordinated job are obstacles on every site (the
  // server does not know the site of a robot that has had no job).
  std::vector<RobotRecord> robots = registry_->Snapshot();
  std::vector<TrafficWaitChange> changes;
  std::vector<std::pair<std::string, ClearanceNotice>> sends;
  {
    absl::MutexLock lock(&mutex_);
    std::map<std::string, const RobotRecord*> by_id;
    for (const RobotRecord& r : robots) by_id[r.identity.robot_id] = &r;
    std::set<std::string> coordinated;
    for (auto& [job_id, tracked] : jobs_) {
      coordinated.insert(tracked.robot_id);
      auto it = by_id.find(tracked.robot_id);
      if (it == by_id.end() || !it->second->last_telemetry) continue;
      const Telemetry& telemetry = *it->second->last_telemetry;
      if (tracked.schedule) {
        // Segments end where the robot reaches their gates.
        PassGates(tracked, telemetry);
        continue;
      }
      if (tracked.resume_from_telemetry) {
        // After a server restart: the robot is in the action it reports.
        if (telemetry.job_id != job_id) continue;
        tracked.start_action = std::max(tracked.start_action, telemetry.action_index);
      }
      Predict(tracked, telemetry.pose_in_map, telemetry.carried_load_m, StandingMarginM(telemetry));
    }
    for (const auto& [job_id, tracked] : jobs_) {
      // A job still waiting for its robot's pose is looked at again on the next update.
      if (!tracked.schedule) changed_ = true;
    }
    std::map<std::string, std::vector<Tracked*>> by_map;
    // A job resumed after a server restart whose robot has not yet said where it is: nobody
    // else on its map is cleared further until it has (or its job ends), for it may stand in
    // their way.
    std::map<std::string, std::string> unplaced_robot_by_map;
    for (auto& [job_id, tracked] : jobs_) {
      if (tracked.schedule) {
        by_map[tracked.assignment.job.map_id].push_back(&tracked);
      } else if (tracked.resume_from_telemetry) {
        unplaced_robot_by_map.emplace(tracked.assignment.job.map_id, tracked.robot_id);
      }
    }
    // Sweeping every idle robot is only worth it when some job is to be ordered.
    std::vector<planner::ParkedRobot> parked;
    for (size_t i = 0; !by_map.empty() && i < robots.size(); ++i) {
      const RobotRecord& r = robots[i];
      if (coordinated.count(r.identity.robot_id) || !r.last_telemetry ||
          r.connection == ConnectionState::kOffline) {
        continue;
      }
      // Swept again only when the robot has moved or its load changed.
      const Pose2& pose = r.last_telemetry->pose_in_map;
      const std::optional<Eigen::Vector2d>& load_m = r.last_telemetry->carried_load_m;
      const double margin_m = StandingMarginM(*r.last_telemetry);
      auto [cached, inserted] = parked_cells_.try_emplace(r.identity.robot_id);
      if (inserted || !cached->second.pose.IsNear(pose, 0.0, 0.0) ||
          cached->second.carried_load_m != load_m ||
          std::abs(cached->second.margin_m - margin_m) > 0.5 * params_.cell_m) {
        cached->second = {
            pose, load_m, margin_m,
            planner::CellSet::Sweep({pose}, r.identity.model.FootprintCarrying(load_m), margin_m,
                                    params_.cell_m)};
      }
      parked.push_back({r.identity.robot_id, cached->second.cells});
    }
    if (parked_cells_.size() > 2 * robots.size()) parked_cells_.clear();  // robots forgotten
    std::erase_if(deciders_, [&](const auto& entry) { return !by_map.contains(entry.first); });
    for (auto& [map_id, tracked_jobs] : by_map) {
      if (auto unplaced = unplaced_robot_by_map.find(map_id);
          unplaced != unplaced_robot_by_map.end()) {
        const std::string reason = absl::StrCat("waits for ", unplaced->second,
                                                " to report where it is (the server restarted)");
        for (Tracked* t : tracked_jobs) {
          if (reason == t->reason) continue;
          t->reason = reason;
          changes.push_back({t->robot_id, t->assignment.job.job_id, reason});
        }
        continue;
      }
      std::vector<const planner::ScheduledRoute*> routes;
      std::map<std::string, const Tracked*> on_map;
      for (const Tracked* t : tracked_jobs) {
        routes.push_back(&*t->schedule);
        on_map[t->robot_id] = t;
      }
      const std::vector<planner::TrafficClearanceDecision> decisions =
          deciders_[map_id].Decide(routes, parked);
      AskIdleRobotsToMakeWay(map_id, tracked_jobs, decisions, parked, by_id);
      for (size_t i = 0; i < decisions.size(); ++i) {
        Tracked& t = *tracked_jobs[i];
        t.schedule->cleared_up_to = decisions[i].cleared_up_to;
        std::string reason = Describe(decisions[i], on_map);
        if (!decisions[i].waits.empty()) {
          if (auto stuck = cannot_make_way_.find(decisions[i].waits.front().blocker_robot_id);
              stuck != cannot_make_way_.end()) {
            absl::StrAppend(&reason, "; it cannot make way: ", stuck->second);
          }
        }
        const bool reason_changed = reason != t.reason;
        if (reason_changed) {
          t.reason = reason;
          changes.push_back({t.robot_id, t.assignment.job.job_id, reason});
        }
        if (decisions[i].cleared_up_to != t.sent_cleared || reason_changed) {
          t.sent_cleared = decisions[i].cleared_up_to;
          sends.push_back({t.robot_id, Notice(t, decisions[i], on_map, reason)});
        }
      }
    }
  }
  for (const auto& [robot_id, notice] : sends) {
    if (!mailbox_->SendClearance(robot_id, notice)) {
      absl::MutexLock lock(&mutex_);
      auto it = jobs_.find(notice.job_id);
      if (it != jobs_.end()) it->second.sent_cleared = -2;  // try again on the next update
      changed_ = true;
    }
  }
  for (const TrafficWaitChange& change : changes) {
    registry_->SetTrafficWait(change.robot_id, change.reason);
  }
  return changes;
}

void TrafficCoordinator::AskIdleRobotsToMakeWay(
    const std::string& map_id, const std::vector<Tracked*>& tracked_jobs,
    const std::vector<planner::TrafficClearanceDecision>& decisions,
    const std::vector<planner::ParkedRobot>& parked,
    const std::map<std::string, const RobotRecord*>& records) {
  // Robots that can be sent aside, with the job to withdraw first ("" for none): those
  // without a job, and those whose job is held whole before it started.
  std::map<std::string, std::string> movable;
  for (const planner::ParkedRobot& p : parked) movable[p.robot_id] = "";
  for (size_t i = 0; i < decisions.size(); ++i) {
    const planner::ScheduledRoute& route = *tracked_jobs[i]->schedule;
    if (decisions[i].deadlocked && route.first_unfinished == 0 && route.cleared_up_to < 0) {
      movable[route.robot_id] = route.job_id;
    }
  }
  for (size_t i = 0; i < decisions.size(); ++i) {
    for (const planner::TrafficWait& wait : decisions[i].waits) {
      // blocker_action < 0: it stands there.
      auto mover = movable.find(wait.blocker_robot_id);
      if (wait.blocker_action >= 0 || decisions[i].deadlocked || mover == movable.end() ||
          make_way_asked_.contains(wait.blocker_robot_id)) {
        continue;
      }
      auto record = records.find(wait.blocker_robot_id);
      if (record == records.end() || !record->second->last_telemetry) continue;
      const RobotRecord& robot = *record->second;
      const Telemetry& telemetry = *robot.last_telemetry;
      // What the others still need: every unfinished action and its end, and where the other
      // idle robots stand.
      planner::MakeWayRequestGeometry geometry;
      geometry.from_in_map = telemetry.pose_in_map;
      geometry.footprint_m = robot.identity.model.FootprintCarrying(telemetry.carried_load_m);
      geometry.margin_m = StandingMarginM(telemetry);
      geometry.cell_m = params_.cell_m;
      for (const Tracked* t : tracked_jobs) {
        const planner::ScheduledRoute& route = *t->schedule;
        if (route.robot_id == robot.identity.robot_id) continue;  // its own, withdrawn
        for (size_t k = std::max(route.first_unfinished, 0); k < route.action_cells.size(); ++k) {
          geometry.keep_off.push_back(&route.action_cells[k]);
          geometry.keep_off.push_back(&route.action_end_cells[k]);
        }
        if (route.first_unfinished == 0) geometry.keep_off.push_back(&route.start_cells);
      }
      for (const planner::ParkedRobot& other : parked) {
        if (other.robot_id != robot.identity.robot_id) geometry.keep_off.push_back(&other.cells);
      }
      PlannerCache& cache =
          CacheFor(map_id, tracked_jobs[i]->assignment.map_version, robot.identity.model);
      if (cache.costmap == nullptr) continue;
      absl::StatusOr<Pose2> place =
          planner::FindMakeWayPlace(*cache.costmap, cache.map_origin, geometry, params_.make_way);
      make_way_asked_.insert(robot.identity.robot_id);
      if (!place.ok()) {
        cannot_make_way_[robot.identity.robot_id] = std::string(place.status().message());
        continue;
      }
      cannot_make_way_.erase(robot.identity.robot_id);
      make_way_requests_.push_back(
          {robot.identity.robot_id, map_id, *place, decisions[i].robot_id, mover->second});
    }
  }
}

std::vector<MakeWayRequest> TrafficCoordinator::TakeMakeWayRequests() {
  absl::MutexLock lock(&mutex_);
  return std::exchange(make_way_requests_, {});
}

}  // namespace fleetnav::server
