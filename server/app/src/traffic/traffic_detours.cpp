// TrafficCoordinator, part four: ways round robots that stand. A robot whose next
// free-navigation step waits for one standing in its way (parked, or held) is planned a way
// round every robot that stands and drives it; issue 35's coordinated paths, in space.
#include <cmath>
#include <optional>
#include <utility>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/planner/coordination/detour.hpp"
#include "fleetnav/server/traffic/traffic_coordinator.hpp"

namespace fleetnav::server {
namespace {

/// A way round is taken up only while the robot stands this near where it was searched from.
constexpr double kDetourFromToleranceM = 0.25;

}  // namespace

void TrafficCoordinator::PlanDetours(
    const std::string& map_id, const std::vector<Tracked*>& tracked_jobs,
    const std::vector<planner::TrafficClearanceDecision>& decisions,
    const std::map<std::string, const RobotRecord*>& records) {
  // One search at a time (each is a lattice search of a hall-sized map): the others are looked
  // at once it has been taken up.
  if (params_.detour_every_s <= 0.0 || detour_ != nullptr) return;
  const double now_s = static_cast<double>(clock_->NowNs()) * 1e-9;
  for (size_t i = 0; i < decisions.size(); ++i) {
    Tracked& t = *tracked_jobs[i];
    const planner::TrafficClearanceDecision& d = decisions[i];
    if (!t.planned_paths || t.needs_prediction || d.waits.empty() ||
        now_s - t.detour_tried_s < params_.detour_every_s) {
      continue;
    }
    // It stands at its gate (everything cleared is done) and waits for one that stands there;
    // or its route is held whole and it stands (the other route's robot may stand in its way:
    // a way round it lets the two be ordered).
    const planner::TrafficWait& wait = d.waits.front();
    const planner::ScheduledRoute& route = *t.schedule;
    const bool standing = d.cleared_up_to < route.first_unfinished;
    if (!standing || (!d.deadlocked && wait.blocker_action >= 0)) continue;
    const int action = ActionOfStep(t, route.first_unfinished);
    if (action < 0 || action >= static_cast<int>(t.assignment.route->actions.size())) continue;
    const auto* nav =
        std::get_if<FreeNavigationAction>(&t.assignment.route->actions[action].params);
    auto record = records.find(t.robot_id);
    if (nav == nullptr || record == records.end() || !record->second->last_telemetry ||
        (planner::RouteBegun(route) && !nav->waypoints_m.empty())) {
      continue;
    }
    t.detour_tried_s = now_s;
    absl::StatusOr<std::shared_ptr<const storage::StoredMap>> map =
        site_data_->Map(map_id, t.assignment.map_version);
    if (map.ok()) {
      PlanWayRound(t, action, *nav, *record->second, *std::move(map), tracked_jobs, decisions,
                   records);
    }
    return;
  }
}

void TrafficCoordinator::PlanWayRound(
    Tracked& t, int action, const FreeNavigationAction& nav, const RobotRecord& robot,
    std::shared_ptr<const storage::StoredMap> map, const std::vector<Tracked*>& tracked_jobs,
    const std::vector<planner::TrafficClearanceDecision>& decisions,
    const std::map<std::string, const RobotRecord*>& records) {
  // Robots that stand: those with no job on the site (any robot not tracked here), those held
  // whole, and those cleared no further than where they are.
  std::map<std::string, bool> stands;
  for (const auto& [robot_id, record] : records) stands[robot_id] = true;
  for (size_t i = 0; i < decisions.size(); ++i) {
    const planner::ScheduledRoute& route = *tracked_jobs[i]->schedule;
    stands[route.robot_id] =
        decisions[i].deadlocked || decisions[i].cleared_up_to < route.first_unfinished;
  }
  // Their floor grown by this robot's swept margin too, so the way keeps off them as traffic
  // coordination keeps a moving robot off one that stands.
  const Telemetry& telemetry = *robot.last_telemetry;
  const double swept_margin_m = SweptMarginM(t.model, telemetry);
  std::vector<planner::CellSet> blocked;
  for (const auto& [robot_id, standing] : stands) {
    auto other = records.find(robot_id);
    if (standing && robot_id != t.robot_id && other != records.end() &&
        other->second->last_telemetry && other->second->connection != ConnectionState::kOffline) {
      blocked.push_back(WhereItStands(*other->second, swept_margin_m));
    }
  }
  std::shared_ptr<const storage::StoredZoneSet> zones = NoGoZonesOf(map->info.map_id);
  // From where it stands through the action's own waypoints to its goal. (Under way, which of
  // its own waypoints are behind it is not known: such an action is not planned again.)
  GiveWayRound(
      t, action, nav, telemetry, {},
      [this, map = std::move(map), zones = std::move(zones), blocked = std::move(blocked), nav,
       model = t.model, from = telemetry.pose_in_map] {
        std::vector<const planner::CellSet*> blocked_pointers;
        for (const planner::CellSet& cells : blocked) blocked_pointers.push_back(&cells);
        // Round the no-go zones, as the agent plans.
        std::optional<OccupancyGrid> with_zones;
        return planner::PlanDetour(
            PlanningGrid(map->grid, zones != nullptr ? &zones->zones : nullptr, with_zones), model,
            blocked_pointers, params_.cell_m, from, nav, params_.detour);
      },
      records);
}

void TrafficCoordinator::GiveWayRound(
    Tracked& t, int action, const FreeNavigationAction& nav, const Telemetry& telemetry,
    std::vector<Eigen::Vector2d> stops,
    std::function<absl::StatusOr<std::vector<Eigen::Vector2d>>()> way,
    const std::map<std::string, const RobotRecord*>& records) {
  auto detour = std::make_shared<PendingDetour>();
  detour->job_id = t.assignment.job.job_id;
  detour->revision = t.revision;
  detour->action = action;
  detour->from = telemetry.pose_in_map;
  detour->assigned_s = static_cast<double>(clock_->NowNs()) * 1e-9;
  detour->stops = std::move(stops);
  // Its window is predicted again from that action along the new way.
  PredictionInput input = PredictionInputOf(t, telemetry);
  input.start_action = action;
  input.assigned_s = detour->assigned_s;
  const bool begun = planner::RouteBegun(*t.schedule);
  const uint64_t path_id = next_path_id_++;
  detour_ = detour;
  detour->given = GiveSearch([this, detour, way = std::move(way), goal = nav.goal,
                              input = std::move(input), begun, path_id]() mutable {
    absl::StatusOr<std::vector<Eigen::Vector2d>> waypoints = way();
    if (!waypoints.ok()) return;  // it waits on; the robot in its way may be sent aside
    detour->path = ActionPath{detour->action, path_id, *std::move(waypoints)};
    if (begun) {
      // Under way, the robot stands where it is until the new way is cleared.
      const std::vector<Eigen::Vector2d>& path = detour->path.waypoints_m;
      const Eigen::Vector2d first = path.empty() ? goal.translation() : path.front();
      const Eigen::Vector2d towards = first - input.pose.translation();
      const double yaw_rad =
          towards.norm() > 1e-6 ? std::atan2(towards.y(), towards.x()) : input.pose.yaw_rad();
      detour->hold_under_way =
          SegmentHold{detour->action, 0, Pose2(input.pose.x_m(), input.pose.y_m(), yaw_rad)};
    }
    input.paths[detour->action] = detour->path;
    input.stops[detour->action] = detour->stops;
    input.hold_under_way = detour->hold_under_way;
    detour->prediction =
        PredictWindow(input, SearchCacheFor(input.map_id, input.map_version, input.model));
    // The agent plans through the waypoints as the prediction did: a way it could not follow
    // (a corner it cannot reach facing on) is never sent. In a generated hall one was, and the
    // robot's job failed.
    detour->found = detour->prediction.planned;
  });
  // Without the search thread it has run: taken up at once.
  if (Finished(detour->given)) TakeDetour(records);
}

void TrafficCoordinator::TakeDetour(const std::map<std::string, const RobotRecord*>& records) {
  const std::shared_ptr<PendingDetour> detour = std::move(detour_);
  detour_.reset();
  if (!detour->found) return;
  auto it = jobs_.find(detour->job_id);
  if (it == jobs_.end()) return;
  Tracked& t = it->second;
  // Of no use once the job has moved on, or the robot has left where the way starts.
  if (t.revision != detour->revision || t.needs_prediction) return;
  auto record = records.find(t.robot_id);
  if (record == records.end() || !record->second->last_telemetry ||
      !record->second->last_telemetry->pose_in_map.IsNear(detour->from, kDetourFromToleranceM,
                                                          kPi)) {
    return;
  }
  t.paths[detour->action] = detour->path;
  t.stops[detour->action] = detour->stops;
  t.hold_under_way = detour->hold_under_way;
  t.start_action = detour->action;
  t.assigned_s = detour->assigned_s;
  t.sent_cleared = -2;
  TakePrediction(t, std::move(detour->prediction));
  changed_ = true;  // decided again along the new way
}

}  // namespace fleetnav::server
