#include "fleetnav/server/traffic/traffic_coordinator.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/segment_gate.hpp"
#include "fleetnav/planner/coordination/make_way.hpp"
#include "fleetnav/planner/coordination/route_segments.hpp"
#include "fleetnav/planner/coordination/wait_cycles.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"

namespace fleetnav::server {
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
  if (!std::isfinite(tracking_allowance_m) || tracking_allowance_m < 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("tracking_allowance_m: must be >= 0, got ", tracking_allowance_m));
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
  if (!std::isfinite(break_cycle_every_s) || break_cycle_every_s <= 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("break_cycle_every_s: must be > 0, got ", break_cycle_every_s));
  }
  if (!std::isfinite(detour_every_s) || detour_every_s < 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("detour_every_s: must be >= 0 (0: never), got ", detour_every_s));
  }
  if (!std::isfinite(step_aside_dwell_s) || step_aside_dwell_s < 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("step_aside_dwell_s: must be >= 0, got ", step_aside_dwell_s));
  }
  if (absl::Status s = detour.Validate(); !s.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("detour.", s.message()));
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
    tracked.planned_paths = record->identity.planned_paths;
  }
  tracked.assigned_s = static_cast<double>(clock_->NowNs()) * 1e-9;
  tracked.start_action = std::max(resume_action, 0);
  tracked.resume_from_telemetry = resume_action == kResumeWhereReported;
  jobs_[assignment.job.job_id] = std::move(tracked);
  make_way_asked_.erase(robot_id);
  cannot_make_way_.erase(robot_id);
  changed_ = true;
}

void TrafficCoordinator::StartSearchThread(std::function<void()> on_searched) {
  searches_.Start(std::move(on_searched));
}

void TrafficCoordinator::StopSearchThread() { searches_.Stop(); }

bool TrafficCoordinator::SearchesPending() {
  absl::MutexLock lock(&mutex_);
  if (detour_ != nullptr) return true;
  return std::any_of(jobs_.begin(), jobs_.end(),
                     [](const auto& entry) { return entry.second.prediction != nullptr; });
}

void TrafficCoordinator::WaitForSearches() { searches_.WaitForAll(); }

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
  if (tracked.hold_under_way && tracked.hold_under_way->action_index <= action_index) {
    tracked.hold_under_way.reset();
  }
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
      // The next window is predicted on the next update, from where the robot then is; the
      // window in force stays until it is taken up.
      tracked.start_action = first_unfinished_action;
      tracked.needs_prediction = true;
      tracked.assigned_s = static_cast<double>(clock_->NowNs()) * 1e-9;
    }
  }
  ++tracked.revision;  // a search under way started from before this action's end
}

void TrafficCoordinator::End(const std::string& job_id) {
  std::string robot_id;
  {
    absl::MutexLock lock(&mutex_);
    auto it = jobs_.find(job_id);
    if (it == jobs_.end()) return;
    robot_id = it->second.robot_id;
    last_zone_lanes_[robot_id] = std::move(it->second.zone_lanes);
    jobs_.erase(it);
    changed_ = true;
    // It stands anew: it may be asked to make way again. (A request made while its job was held
    // may have been dropped: a make-way job is not withdrawn.)
    make_way_asked_.erase(robot_id);
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
    ++updates_;
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
      // Segments end where the robot reaches their gates.
      if (tracked.schedule) PassGates(tracked, telemetry);
      if (!tracked.needs_prediction) continue;
      // A prediction given before the job moved on is of no use.
      if (tracked.prediction && tracked.prediction->revision != tracked.revision) {
        tracked.prediction.reset();
      }
      if (!tracked.prediction) {
        if (tracked.resume_from_telemetry && !tracked.schedule) {
          // After a server restart: the robot is in the action it reports.
          if (telemetry.job_id != job_id) continue;
          tracked.start_action = std::max(tracked.start_action, telemetry.action_index);
        }
        GivePrediction(tracked, telemetry);
      }
      if (Finished(tracked.prediction->given)) {
        TakePrediction(tracked, std::move(tracked.prediction->result));
      }
    }
    for (const auto& [job_id, tracked] : jobs_) {
      // A job still waiting for its robot's pose, or for its prediction, is looked at again on
      // the next update.
      if (tracked.needs_prediction) changed_ = true;
    }
    if (detour_ != nullptr && Finished(detour_->given)) TakeDetour(by_id);
    if (detour_ != nullptr) changed_ = true;  // taken up once it has been searched
    // A robot whose job is still to be predicted stands where it is, as one without a job does,
    // but is not sent aside.
    awaiting_prediction_.clear();
    for (auto& [job_id, tracked] : jobs_) {
      if (!tracked.schedule) {
        coordinated.erase(tracked.robot_id);
        awaiting_prediction_.insert(tracked.robot_id);
      }
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
      std::vector<planner::ParkedRobot> parked_in_zones;
      const std::vector<planner::ParkedRobot>& parked_here =
          ParkedWithCapacityZones(map_id, parked, parked_in_zones);
      std::vector<planner::TrafficClearanceDecision> decisions =
          deciders_[map_id].Decide(routes, parked_here);
      HoldClearOfWhereRobotsAre(tracked_jobs, decisions, by_id);
      AskIdleRobotsToMakeWay(map_id, tracked_jobs, decisions, parked_here, by_id);
      BreakWaitCycles(map_id, tracked_jobs, decisions, parked_here, by_id);
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
      PlanDetours(map_id, tracked_jobs, decisions, by_id);
      PlanWaysRoundStops(map_id, tracked_jobs, by_id);
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

void TrafficCoordinator::HoldClearOfWhereRobotsAre(
    const std::vector<Tracked*>& tracked_jobs,
    std::vector<planner::TrafficClearanceDecision>& decisions,
    const std::map<std::string, const RobotRecord*>& records) {
  // Where each robot of the map stands now: swept only when some decision clears anything new.
  const auto first_new = [&](size_t i) {
    const planner::ScheduledRoute& route = *tracked_jobs[i]->schedule;
    return std::max(route.cleared_up_to, route.first_unfinished - 1) + 1;
  };
  bool clears_new = false;
  for (size_t i = 0; i < decisions.size() && !clears_new; ++i) {
    clears_new = first_new(i) <= decisions[i].cleared_up_to;
  }
  if (!clears_new) return;
  std::vector<std::pair<std::string, planner::CellSet>> now;
  for (const Tracked* t : tracked_jobs) {
    auto record = records.find(t->robot_id);
    if (record == records.end() || !record->second->last_telemetry) continue;
    now.emplace_back(t->robot_id, WhereItStands(*record->second));
  }
  for (size_t i = 0; i < decisions.size(); ++i) {
    planner::TrafficClearanceDecision& d = decisions[i];
    const planner::ScheduledRoute& route = *tracked_jobs[i]->schedule;
    for (int k = first_new(i); k <= d.cleared_up_to; ++k) {
      auto in_way = std::find_if(now.begin(), now.end(), [&](const auto& other) {
        return other.first != route.robot_id && route.action_cells[k].Intersects(other.second);
      });
      if (in_way == now.end()) continue;
      d.cleared_up_to = k - 1;
      d.waits = {planner::TrafficWait{route.robot_id, k, in_way->first, -1}};
      break;
    }
  }
}

void TrafficCoordinator::AskIdleRobotsToMakeWay(
    const std::string& map_id, const std::vector<Tracked*>& tracked_jobs,
    const std::vector<planner::TrafficClearanceDecision>& decisions,
    const std::vector<planner::ParkedRobot>& parked,
    const std::map<std::string, const RobotRecord*>& records) {
  // Robots that can be sent aside, with the job to withdraw first ("" for none): those
  // without a job, and those whose job is held whole before it started.
  std::map<std::string, std::string> movable;
  for (const planner::ParkedRobot& p : parked) {
    if (!awaiting_prediction_.contains(p.robot_id)) movable[p.robot_id] = "";
  }
  for (size_t i = 0; i < decisions.size(); ++i) {
    const planner::ScheduledRoute& route = *tracked_jobs[i]->schedule;
    if (decisions[i].deadlocked && !planner::RouteBegun(route)) {
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
      absl::StatusOr<Pose2> place = PlaceAside(map_id, tracked_jobs[i]->assignment.map_version,
                                               robot, tracked_jobs, parked, records);
      if (absl::IsUnavailable(place.status())) continue;
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

absl::StatusOr<Pose2> TrafficCoordinator::PlaceAside(
    const std::string& map_id, uint32_t map_version, const RobotRecord& robot,
    const std::vector<Tracked*>& tracked_jobs, const std::vector<planner::ParkedRobot>& parked,
    const std::map<std::string, const RobotRecord*>& records,
    const std::vector<std::string>* near_only_except) {
  const Telemetry& telemetry = *robot.last_telemetry;
  // What the others still need: every unfinished action and its end, and where the other idle
  // robots stand.
  planner::MakeWayRequestGeometry geometry;
  geometry.from_in_map = telemetry.pose_in_map;
  geometry.footprint_m = robot.identity.model.FootprintCarrying(telemetry.carried_load_m);
  geometry.margin_m = StandingMarginM(telemetry);
  geometry.cell_m = params_.cell_m;
  for (const Tracked* t : tracked_jobs) {
    const planner::ScheduledRoute& route = *t->schedule;
    if (route.robot_id == robot.identity.robot_id) continue;  // its own, withdrawn
    size_t end = route.action_cells.size();
    if (near_only_except != nullptr && std::find(near_only_except->begin(), near_only_except->end(),
                                                 route.robot_id) == near_only_except->end()) {
      end = std::min(end, static_cast<size_t>(std::max(route.cleared_up_to, -1) + 2));
      if (!route.action_end_cells.empty())
        geometry.keep_off.push_back(&route.action_end_cells.back());
    }
    for (size_t k = std::max(route.first_unfinished, 0); k < end; ++k) {
      geometry.keep_off.push_back(&route.action_cells[k]);
      geometry.keep_off.push_back(&route.action_end_cells[k]);
    }
    if (route.first_unfinished == 0) geometry.keep_off.push_back(&route.start_cells);
  }
  for (const planner::ParkedRobot& other : parked) {
    if (other.robot_id != robot.identity.robot_id) {
      geometry.keep_off.push_back(&other.cells);
      geometry.impassable.push_back(&other.cells);
    }
  }
  // Where the robots with jobs on this map stand now.
  std::vector<planner::CellSet> standing;
  standing.reserve(tracked_jobs.size());
  for (const Tracked* t : tracked_jobs) {
    auto other = records.find(t->robot_id);
    if (t->robot_id != robot.identity.robot_id && other != records.end() &&
        other->second->last_telemetry) {
      standing.push_back(WhereItStands(*other->second));
    }
  }
  for (const planner::CellSet& cells : standing) geometry.impassable.push_back(&cells);
  geometry.pass_margin_m = params_.margin_m;
  PlannerCache& cache = CacheFor(map_id, map_version, robot.identity.model);
  if (cache.costmap == nullptr) {
    return absl::UnavailableError(absl::StrCat("map '", map_id, "' is not loaded"));
  }
  absl::StatusOr<Pose2> place =
      planner::FindMakeWayPlace(*cache.costmap, cache.map_origin, geometry, params_.make_way);
  if (!absl::IsNotFound(place.status())) return place;
  // Boxed in by the others: a place it reaches only past someone is still better than none.
  geometry.impassable.clear();
  return planner::FindMakeWayPlace(*cache.costmap, cache.map_origin, geometry, params_.make_way);
}

void TrafficCoordinator::BreakWaitCycles(
    const std::string& map_id, const std::vector<Tracked*>& tracked_jobs,
    const std::vector<planner::TrafficClearanceDecision>& decisions,
    const std::vector<planner::ParkedRobot>& parked,
    const std::map<std::string, const RobotRecord*>& records) {
  const double now_s = static_cast<double>(clock_->NowNs()) * 1e-9;
  for (const std::vector<std::string>& cycle : planner::FindWaitCycles(decisions)) {
    // A circle one of whose robots was sent aside lately is being broken: left alone.
    if (std::any_of(cycle.begin(), cycle.end(), [&](const std::string& robot_id) {
          auto broken = cycle_breaks_.find(robot_id);
          return broken != cycle_breaks_.end() &&
                 now_s - broken->second.last_s < params_.break_cycle_every_s;
        })) {
      continue;
    }
    const auto in_cycle = [&](const std::string& robot_id) {
      return std::find(cycle.begin(), cycle.end(), robot_id) != cycle.end();
    };
    // Who in the circle stands in the way of another of it (and who waits for it).
    std::map<std::string, std::string> stands_in_way_of;
    for (const planner::TrafficClearanceDecision& d : decisions) {
      if (!in_cycle(d.robot_id)) continue;
      for (const planner::TrafficWait& wait : d.waits) {
        if (wait.blocker_action < 0 && in_cycle(wait.blocker_robot_id)) {
          stands_in_way_of.emplace(wait.blocker_robot_id, d.robot_id);
        }
      }
    }
    // The robot to send aside: one that has not started its job (it stands at its start and
    // can drop it). Of those, the one sent aside for a circle least often (a circle that forms
    // again after a robot went aside is broken by another: in the dense hall one robot's place
    // aside was found the same each time, and its way there met the same neighbour), then one
    // that stands in the way of another (moving it clears a way), then the one expected to
    // start last (of equals, the later one, as DecideClearances holds the newer).
    int chosen = -1;
    const auto rank = [&](int i) {
      const planner::ScheduledRoute& route = *tracked_jobs[i]->schedule;
      auto broken = cycle_breaks_.find(route.robot_id);
      return std::make_tuple(broken == cycle_breaks_.end() ? 0 : -broken->second.count,
                             stands_in_way_of.contains(route.robot_id), route.action_start_s[0]);
    };
    for (size_t i = 0; i < decisions.size(); ++i) {
      const planner::ScheduledRoute& route = *tracked_jobs[i]->schedule;
      if (!in_cycle(route.robot_id) || planner::RouteBegun(route) || route.action_start_s.empty()) {
        continue;
      }
      if (chosen < 0 || rank(static_cast<int>(i)) >= rank(chosen)) chosen = static_cast<int>(i);
    }
    // One sent aside for a circle before that is in a circle again may be boxed in by a robot
    // under way, standing at its gate, whose way it must leave by (in a generated dense hall a
    // robot at a pack station could leave only past the next robot to it, and was sent to one
    // place after another for 30 minutes): that robot steps aside within its action instead.
    // So does one when no robot of the circle can drop its job; each steps aside less often
    // than the other was sent.
    const auto breaks_of = [&](const std::string& robot_id) {
      auto broken = cycle_breaks_.find(robot_id);
      return broken == cycle_breaks_.end() ? 0 : broken->second.count;
    };
    const int chosen_breaks = chosen < 0 ? 1 : breaks_of(tracked_jobs[chosen]->robot_id);
    bool stepped_aside = false;
    for (size_t i = 0; i < decisions.size() && chosen_breaks > 0 && !stepped_aside; ++i) {
      if (in_cycle(tracked_jobs[i]->robot_id) &&
          breaks_of(tracked_jobs[i]->robot_id) < chosen_breaks) {
        stepped_aside = StepAsideUnderWay(map_id, *tracked_jobs[i], decisions[i], tracked_jobs,
                                          parked, records);
      }
    }
    if (stepped_aside) continue;
    if (chosen < 0) continue;
    const Tracked& tracked = *tracked_jobs[chosen];
    auto record = records.find(tracked.robot_id);
    if (record == records.end() || !record->second->last_telemetry) continue;
    CycleBreaks& breaks = cycle_breaks_[tracked.robot_id];
    breaks.last_s = now_s;
    ++breaks.count;
    if (auto asked =
            std::find_if(make_way_requests_.begin(), make_way_requests_.end(),
                         [&](const MakeWayRequest& r) { return r.robot_id == tracked.robot_id; });
        asked != make_way_requests_.end()) {
      // Already sent aside on this pass (its job held whole): it breaks the circle.
      asked->breaks_wait_cycle = true;
      continue;
    }
    absl::StatusOr<Pose2> place = PlaceAside(map_id, tracked.assignment.map_version,
                                             *record->second, tracked_jobs, parked, records);
    if (absl::IsNotFound(place.status())) {
      // Off the circle's ways and whatever the others do next: the rest waits its turn.
      place = PlaceAside(map_id, tracked.assignment.map_version, *record->second, tracked_jobs,
                         parked, records, &cycle);
    }
    if (!place.ok()) {
      // Said in the reason of whoever waits for it.
      cannot_make_way_[tracked.robot_id] = std::string(place.status().message());
      continue;
    }
    // Someone in the circle waits for it (standing in its way, if it does).
    std::string for_robot_id;
    if (auto waiter = stands_in_way_of.find(tracked.robot_id); waiter != stands_in_way_of.end()) {
      for_robot_id = waiter->second;
    }
    for (size_t i = 0; i < decisions.size() && for_robot_id.empty(); ++i) {
      for (const planner::TrafficWait& wait : decisions[i].waits) {
        if (wait.blocker_robot_id == tracked.robot_id && in_cycle(decisions[i].robot_id)) {
          for_robot_id = decisions[i].robot_id;
        }
      }
    }
    make_way_requests_.push_back({tracked.robot_id, map_id, *place, for_robot_id,
                                  tracked.assignment.job.job_id, /*breaks_wait_cycle=*/true});
  }
}

bool TrafficCoordinator::StepAsideUnderWay(
    const std::string& map_id, Tracked& t, const planner::TrafficClearanceDecision& d,
    const std::vector<Tracked*>& tracked_jobs, const std::vector<planner::ParkedRobot>& parked,
    const std::map<std::string, const RobotRecord*>& records) {
  if (!t.planned_paths || t.needs_prediction || !t.schedule || detour_ != nullptr) return false;
  const planner::ScheduledRoute& route = *t.schedule;
  // Under way, standing at its gate with all it was cleared for done.
  if (!planner::RouteBegun(route) || d.deadlocked || d.cleared_up_to >= route.first_unfinished) {
    return false;
  }
  const int action = ActionOfStep(t, route.first_unfinished);
  if (action < 0 || action >= static_cast<int>(t.assignment.route->actions.size())) return false;
  // Which of its own waypoints are behind it is not known: only an action without them.
  const auto* nav = std::get_if<FreeNavigationAction>(&t.assignment.route->actions[action].params);
  auto record = records.find(t.robot_id);
  if (nav == nullptr || !nav->waypoints_m.empty() || record == records.end() ||
      !record->second->last_telemetry) {
    return false;
  }
  absl::StatusOr<Pose2> place =
      PlaceAside(map_id, t.assignment.map_version, *record->second, tracked_jobs, parked, records);
  if (!place.ok()) return false;
  const Telemetry& telemetry = *record->second->last_telemetry;
  if ((place->translation() - telemetry.pose_in_map.translation()).norm() < params_.cell_m) {
    return false;  // it stands there already
  }
  CycleBreaks& breaks = cycle_breaks_[t.robot_id];
  breaks.last_s = static_cast<double>(clock_->NowNs()) * 1e-9;
  ++breaks.count;
  // Through the place aside, where it stands until cleared on, to the action's goal; it
  // stands where it is until that way is cleared.
  const Eigen::Vector2d aside = place->translation();
  GiveWayRound(
      t, action, *nav, telemetry, {aside},
      [aside]() -> absl::StatusOr<std::vector<Eigen::Vector2d>> {
        return std::vector<Eigen::Vector2d>{aside};
      },
      records);
  return true;
}

std::vector<MakeWayRequest> TrafficCoordinator::TakeMakeWayRequests() {
  absl::MutexLock lock(&mutex_);
  return std::exchange(make_way_requests_, {});
}

}  // namespace fleetnav::server
