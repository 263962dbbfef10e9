// TrafficCoordinator, part six: ways round closed zones (issue 39) — operators' stopped zones,
// and no-go zones put while a robot drives an action planned without them. A robot outside them
// whose free-navigation action crosses one is planned a way round, as round robots that stand;
// meanwhile its agent brakes to stand before the zone (agent::KeepOffStoppedZones), and drives
// the way round once it comes. A robot in such a zone, or one whose goal is in it, stands.
#include <algorithm>
#include <cmath>
#include <limits>

#include "fleetnav/core/segment_distance.hpp"
#include "fleetnav/planner/coordination/detour.hpp"
#include "fleetnav/server/traffic/traffic_coordinator.hpp"

namespace fleetnav::server {
namespace {

/// How near its centre the footprint's edge comes (base_link's distance to the nearest edge).
double InscribedRadiusM(const Polygon2& footprint) {
  double out = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < footprint.size(); ++i) {
    out = std::min(out, PointSegmentDistance(Eigen::Vector2d::Zero(), footprint[i],
                                             footprint[(i + 1) % footprint.size()]));
  }
  return std::isfinite(out) ? out : 0.0;
}

}  // namespace

std::vector<Eigen::Vector2d> TrafficCoordinator::WaypointsAhead(const FreeNavigationAction& nav,
                                                                const Eigen::Vector2d& at) {
  // The polyline through the waypoints to the goal: the robot is past every waypoint before
  // the leg it is nearest to.
  std::vector<Eigen::Vector2d> points = nav.waypoints_m;
  points.push_back(nav.goal.translation());
  size_t first = 0;
  double nearest_m = (points.front() - at).norm();
  for (size_t k = 1; k < points.size(); ++k) {
    const double distance_m = PointSegmentDistance(at, points[k - 1], points[k]);
    if (distance_m < nearest_m) {
      nearest_m = distance_m;
      first = k;
    }
  }
  return {nav.waypoints_m.begin() +
              static_cast<std::ptrdiff_t>(std::min(first, nav.waypoints_m.size())),
          nav.waypoints_m.end()};
}

void TrafficCoordinator::SetStops(std::vector<RobotStop> stops) {
  absl::MutexLock lock(&mutex_);
  stops_ = std::move(stops);
  changed_ = true;
}

void TrafficCoordinator::ZonesChanged() {
  absl::MutexLock lock(&mutex_);
  changed_ = true;
}

std::vector<size_t> TrafficCoordinator::NoGoZonesNewTo(const storage::StoredZoneSet& latest,
                                                       uint32_t given_version) {
  // The job's own version, read once per (map, version).
  std::shared_ptr<const ZoneSet> given;
  if (given_version > 0 && zones_ != nullptr) {
    const auto key = std::make_pair(latest.zones.map_id, given_version);
    auto it = given_zone_sets_.find(key);
    if (it == given_zone_sets_.end()) {
      absl::StatusOr<storage::StoredZoneSet> read =
          zones_->GetZones(latest.zones.map_id, given_version);
      it = given_zone_sets_
               .emplace(key, read.ok() ? std::make_shared<const ZoneSet>(std::move(read->zones))
                                       : nullptr)
               .first;
    }
    given = it->second;
  }
  std::vector<size_t> out;
  for (size_t i = 0; i < latest.zones.zones.size(); ++i) {
    const Zone& zone = latest.zones.zones[i];
    const Zone* before = given != nullptr ? given->Find(zone.name) : nullptr;
    if (zone.kind == ZoneKind::kNoGo && (before == nullptr || before->kind != ZoneKind::kNoGo ||
                                         before->polygon_in_map != zone.polygon_in_map)) {
      out.push_back(i);
    }
  }
  return out;
}

void TrafficCoordinator::PlanWaysRoundStops(
    const std::string& map_id, const std::vector<Tracked*>& tracked_jobs,
    const std::map<std::string, const RobotRecord*>& records) {
  if (params_.detour_every_s <= 0.0 || detour_ != nullptr) return;
  // Closed: the stopped zones, and for a job given before the map's latest zones those of their
  // no-go zones that its own version did not have (its agent planned its action in hand
  // without them).
  std::vector<const Polygon2*> stopped;
  for (const RobotStop& stop : stops_) {
    if (!stop.whole_fleet() && stop.map_id == map_id && stop.polygon_in_map.size() >= 3) {
      stopped.push_back(&stop.polygon_in_map);
    }
  }
  const std::shared_ptr<const storage::StoredZoneSet> zones = NoGoZonesOf(map_id);
  if (stopped.empty() && zones == nullptr) return;
  const auto cells_of = [&](const std::vector<const Polygon2*>& polygons, double grow_m) {
    std::vector<planner::CellSet> out;
    for (const Polygon2* polygon : polygons) {
      out.push_back(planner::CellSet::Sweep({Pose2()}, *polygon, grow_m, params_.cell_m));
    }
    return out;
  };
  const std::vector<planner::CellSet> stopped_cells = cells_of(stopped, 0.0);
  const double now_s = static_cast<double>(clock_->NowNs()) * 1e-9;
  for (Tracked* tracked : tracked_jobs) {
    Tracked& t = *tracked;
    if (!t.planned_paths || t.needs_prediction || !t.schedule ||
        now_s - t.detour_tried_s < params_.detour_every_s) {
      continue;
    }
    const planner::ScheduledRoute& route = *t.schedule;
    const int action = ActionOfStep(t, route.first_unfinished);
    if (action < 0 || action >= static_cast<int>(t.assignment.route->actions.size())) continue;
    const auto* nav =
        std::get_if<FreeNavigationAction>(&t.assignment.route->actions[action].params);
    auto record = records.find(t.robot_id);
    if (nav == nullptr || record == records.end() || !record->second->last_telemetry) continue;
    // A robot in a stopped zone stands there; one whose action's steps meet none goes on.
    std::vector<const Polygon2*> closed = stopped;
    std::vector<planner::CellSet> closed_cells = stopped_cells;
    if (zones != nullptr && t.assignment.zone_set_version != zones->version) {
      for (const size_t z : NoGoZonesNewTo(*zones, t.assignment.zone_set_version)) {
        closed.push_back(&zones->zones.zones[z].polygon_in_map);
        closed_cells.push_back(
            planner::CellSet::Sweep({Pose2()}, *closed.back(), 0.0, params_.cell_m));
      }
    }
    if (closed.empty()) continue;
    const planner::CellSet here = WhereItStands(*record->second);
    bool inside = false;
    bool crosses = false;
    for (const planner::CellSet& zone : closed_cells) {
      inside = inside || here.Intersects(zone);
      for (int s = route.first_unfinished;
           !crosses && s < static_cast<int>(route.action_cells.size()) &&
           ActionOfStep(t, s) == action;
           ++s) {
        crosses = route.action_cells[s].Intersects(zone);
      }
    }
    if (inside || !crosses) continue;
    t.detour_tried_s = now_s;
    absl::StatusOr<std::shared_ptr<const storage::StoredMap>> map =
        site_data_->Map(map_id, t.assignment.map_version);
    if (!map.ok()) continue;
    const Telemetry& telemetry = *record->second->last_telemetry;
    // The zones grown so that where the footprint keeps off them, its centre keeps the agent's
    // reach (its body and grown uncertainty) off the zones with a cell to spare: the agent
    // slows a robot only as it nears a stopped zone within that reach.
    const double grow_m = t.model.CircumscribedRadius() - InscribedRadiusM(t.model.footprint_m) +
                          StandingMarginM(telemetry) + params_.cell_m;
    std::vector<planner::CellSet> blocked = cells_of(closed, grow_m);
    // Through its own waypoints still ahead and off the zones.
    FreeNavigationAction ahead = *nav;
    ahead.waypoints_m.clear();
    ahead.waypoint_yaws_rad.clear();
    const double reach_m = t.model.CircumscribedRadius() + StandingMarginM(telemetry);
    for (const Eigen::Vector2d& waypoint :
         WaypointsAhead(*nav, telemetry.pose_in_map.translation())) {
      if (std::none_of(closed.begin(), closed.end(), [&](const Polygon2* polygon) {
            return DiscTouchesPolygon(*polygon, waypoint, reach_m);
          })) {
        ahead.waypoints_m.push_back(waypoint);
      }
    }
    GiveWayRound(
        t, action, ahead, telemetry, {},
        [this, map = *std::move(map), zones, blocked = std::move(blocked), ahead, model = t.model,
         from = telemetry.pose_in_map] {
          std::vector<const planner::CellSet*> blocked_pointers;
          for (const planner::CellSet& cells : blocked) blocked_pointers.push_back(&cells);
          std::optional<OccupancyGrid> with_zones;
          return planner::PlanDetour(
              PlanningGrid(map->grid, zones != nullptr ? &zones->zones : nullptr, with_zones),
              model, blocked_pointers, params_.cell_m, from, ahead, params_.detour);
        },
        records);
    return;  // one search at a time
  }
}

}  // namespace fleetnav::server
