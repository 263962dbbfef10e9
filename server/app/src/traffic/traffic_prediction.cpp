// TrafficCoordinator, part two: where each tracked robot will drive (its actions predicted on
// the site's map with the planner of its kind) and the room it holds while standing.
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <utility>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/segment_gate.hpp"
#include "fleetnav/planner/coordination/make_way.hpp"
#include "fleetnav/planner/coordination/route_segments.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"
#include "fleetnav/server/traffic/traffic_coordinator.hpp"

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

std::shared_ptr<const storage::StoredZoneSet> TrafficCoordinator::NoGoZonesOf(
    const std::string& map_id) const {
  if (zones_ == nullptr) return nullptr;
  std::shared_ptr<const storage::StoredZoneSet> zones = zones_->Latest(map_id);
  return zones != nullptr && zones->zones.HasKind(ZoneKind::kNoGo) ? zones : nullptr;
}

TrafficCoordinator::PlannerCache TrafficCoordinator::BuildPlannerCache(const std::string& map_id,
                                                                       uint32_t map_version,
                                                                       const RobotModel& model,
                                                                       const ZoneSet* zones) const {
  PlannerCache cache;
  absl::StatusOr<std::shared_ptr<const storage::StoredMap>> shared =
      site_data_->Map(map_id, map_version);
  if (!shared.ok()) return cache;
  const storage::StoredMap* map = shared->get();
  // The agent's free navigation plans with 0.1 m of padding (FreeNavigationParams).
  planner::CostmapParams costmap_params;
  costmap_params.padding_m = 0.1;
  // The agent plans round the no-go zones: so does its prediction.
  std::optional<OccupancyGrid> with_zones;
  absl::StatusOr<planner::Costmap> costmap = planner::Costmap::Build(
      PlanningGrid(map->grid, zones, with_zones), model.footprint_m, costmap_params);
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
  return cache;
}

TrafficCoordinator::PlannerCache& TrafficCoordinator::CacheIn(PlannerCaches& caches,
                                                              const std::string& map_id,
                                                              uint32_t map_version,
                                                              const RobotModel& model) const {
  const std::shared_ptr<const storage::StoredZoneSet> zones = NoGoZonesOf(map_id);
  const auto key =
      std::make_tuple(map_id, map_version, model.kind_name, zones != nullptr ? zones->version : 0);
  auto it = caches.find(key);
  if (it == caches.end()) {
    it = caches
             .emplace(key, BuildPlannerCache(map_id, map_version, model,
                                             zones != nullptr ? &zones->zones : nullptr))
             .first;
  }
  return it->second;
}

TrafficCoordinator::PlannerCache& TrafficCoordinator::CacheFor(const std::string& map_id,
                                                               uint32_t map_version,
                                                               const RobotModel& model) {
  return CacheIn(planners_, map_id, map_version, model);
}

TrafficCoordinator::PlannerCache& TrafficCoordinator::SearchCacheFor(const std::string& map_id,
                                                                     uint32_t map_version,
                                                                     const RobotModel& model) {
  return CacheIn(search_planners_, map_id, map_version, model);
}

double TrafficCoordinator::StandingMarginM(const Telemetry& telemetry) const {
  const double variance_m2 = std::max(telemetry.covariance[0], telemetry.covariance[4]);
  if (!std::isfinite(variance_m2) || variance_m2 < 0.0) return params_.margin_m;
  return std::clamp(params_.standing_sigmas * std::sqrt(variance_m2), params_.standing_margin_min_m,
                    params_.margin_m);
}

planner::CellSet TrafficCoordinator::WhereItStands(const RobotRecord& robot, double more_m) const {
  const Telemetry& at = *robot.last_telemetry;
  return planner::CellSet::Sweep({at.pose_in_map},
                                 robot.identity.model.FootprintCarrying(at.carried_load_m),
                                 StandingMarginM(at) + more_m, params_.cell_m);
}

double TrafficCoordinator::SweptMarginM(const RobotModel& model, const Telemetry& telemetry) const {
  if (!FollowsClosely(model)) return params_.margin_m;
  return std::min(StandingMarginM(telemetry) + params_.tracking_allowance_m, params_.margin_m);
}

TrafficCoordinator::PredictionInput TrafficCoordinator::PredictionInputOf(
    const Tracked& tracked, const Telemetry& telemetry) const {
  PredictionInput input;
  input.robot_id = tracked.robot_id;
  input.job_id = tracked.assignment.job.job_id;
  input.map_id = tracked.assignment.job.map_id;
  input.map_version = tracked.assignment.map_version;
  input.route = tracked.assignment.route;
  input.model = tracked.model;
  input.start_action = tracked.start_action;
  input.assigned_s = tracked.assigned_s;
  input.segment_clearances = tracked.segment_clearances;
  input.resume_from_telemetry = tracked.resume_from_telemetry;
  input.paths = tracked.paths;
  input.stops = tracked.stops;
  input.hold_under_way = tracked.hold_under_way;
  input.pose = telemetry.pose_in_map;
  input.carried_load_m = telemetry.carried_load_m;
  input.standing_margin_m = StandingMarginM(telemetry);
  input.swept_margin_m = SweptMarginM(tracked.model, telemetry);
  if (tracked.assignment.marker_set_version > 0) {
    absl::StatusOr<std::shared_ptr<const storage::StoredMarkerSet>> stored =
        site_data_->MarkerSetVersion(tracked.assignment.job.map_id,
                                     tracked.assignment.marker_set_version);
    if (stored.ok()) input.markers = *std::move(stored);
  }
  return input;
}

void TrafficCoordinator::GivePrediction(Tracked& tracked, const Telemetry& telemetry) {
  auto pending = std::make_shared<PendingPrediction>();
  pending->revision = tracked.revision;
  tracked.prediction = pending;
  pending->given = GiveSearch([this, pending, input = PredictionInputOf(tracked, telemetry)] {
    pending->result =
        PredictWindow(input, SearchCacheFor(input.map_id, input.map_version, input.model));
  });
}

TrafficCoordinator::Given TrafficCoordinator::GiveSearch(std::function<void()> search) {
  Given given;
  given.update = updates_;
  given.ran_at_once = !searches_.threaded();
  given.ticket = searches_.Add(std::move(search));
  return given;
}

bool TrafficCoordinator::Finished(const Given& given) {
  return (given.ran_at_once || given.update < updates_) && searches_.Done(given.ticket);
}

void TrafficCoordinator::TakePrediction(Tracked& tracked, Prediction prediction) {
  tracked.schedule = std::move(prediction.schedule);
  tracked.schedule->cells_id = next_cells_id_++;
  tracked.steps = std::move(prediction.steps);
  tracked.predicted_end = prediction.predicted_end;
  KeepCapacityZones(tracked);
  tracked.needs_prediction = false;
  tracked.prediction.reset();
  ++tracked.revision;
}

TrafficCoordinator::Prediction TrafficCoordinator::PredictWindow(const PredictionInput& input,
                                                                 PlannerCache& cache) const {
  Prediction out;
  const std::shared_ptr<const storage::StoredMarkerSet>& markers = input.markers;
  const Pose2& pose = input.pose;
  const std::optional<Eigen::Vector2d>& carried_load_m = input.carried_load_m;
  // Only the window of actions ahead is predicted (horizon_actions).
  const std::vector<RouteAction>& all = input.route->actions;
  const int skipped = std::min<int>(input.start_action, all.size());
  const int end = std::min<int>(all.size(), skipped + params_.horizon_actions);
  Route remaining;
  remaining.name = input.route->name;
  remaining.map_id = input.route->map_id;
  remaining.actions.assign(all.begin() + skipped, all.begin() + end);
  // Ways planned round robots that stand replace what the agent would plan alone.
  for (const auto& [action, path] : input.paths) {
    if (action < skipped || action >= end) continue;
    if (auto* nav =
            std::get_if<FreeNavigationAction>(&remaining.actions[action - skipped].params)) {
      nav->waypoints_m = path.waypoints_m;
      nav->waypoint_yaws_rad.clear();
    }
  }
  out.predicted_end = end;
  const Pose2 map_origin = cache.map_origin;
  planner::SingleRobotPlanner* planner = cache.planner.get();
  const MarkerSet* marker_set = markers ? &markers->markers : nullptr;
  absl::StatusOr<std::vector<planner::PredictedAction>> predicted =
      planner::PredictRoute(remaining, pose, marker_set, planner, map_origin, params_.prediction);
  if (!predicted.ok() && planner != nullptr) {
    // The agent will say why it cannot plan; the straight lines still reserve its way there.
    out.planned = false;
    predicted =
        planner::PredictRoute(remaining, pose, marker_set, nullptr, map_origin, params_.prediction);
  }
  planner::ScheduledRoute schedule;
  schedule.robot_id = input.robot_id;
  schedule.job_id = input.job_id;
  // A robot carrying a trolley sweeps the trolley's outline too (RobotModel::CarryingLoad); the
  // load changes where a trolley dock or an undock ends.
  const auto sweep = [&](const std::vector<Pose2>& poses,
                         const std::optional<Eigen::Vector2d>& load_m) {
    return planner::CellSet::Sweep(poses, input.model.FootprintCarrying(load_m),
                                   input.swept_margin_m, params_.cell_m);
  };
  const auto stand = [&](const Pose2& at, const std::optional<Eigen::Vector2d>& load_m) {
    return planner::CellSet::Sweep({at}, input.model.FootprintCarrying(load_m),
                                   input.standing_margin_m, params_.cell_m);
  };
  std::optional<Eigen::Vector2d> load_m = carried_load_m;
  schedule.start_cells = stand(pose, load_m);
  // Actions already run are one empty step each.
  std::vector<Step>& steps = out.steps;
  for (int k = 0; k < skipped; ++k) {
    steps.push_back({k, 0, 1, std::nullopt});
    schedule.whole_from.push_back(k);
    schedule.action_cells.emplace_back();
    schedule.action_end_cells.push_back(schedule.start_cells);
    schedule.action_start_s.push_back(input.assigned_s);
  }
  const double segment_m =
      input.segment_clearances && FollowsClosely(input.model) ? params_.segment_m : 0.0;
  double t_s = input.assigned_s;
  for (size_t i = 0; i < remaining.actions.size(); ++i) {
    const int action = skipped + static_cast<int>(i);
    if (!predicted.ok()) {
      // Unpredictable (a stripe the marker set lacks): reserve where it stands.
      schedule.whole_from.push_back(static_cast<int>(steps.size()));
      steps.push_back({action, 0, 1, std::nullopt});
      schedule.action_cells.push_back(sweep({pose}, carried_load_m));
      schedule.action_end_cells.push_back(schedule.start_cells);
      schedule.action_start_s.push_back(t_s);
      continue;
    }
    const std::optional<Eigen::Vector2d> load_after_m =
        CarriedLoadAfter(remaining.actions[i], load_m, marker_set, Eigen::Vector2d::Zero());
    const bool free_navigation =
        std::holds_alternative<FreeNavigationAction>(remaining.actions[i].params);
    const auto stops = input.stops.find(action);
    const std::vector<planner::ActionSegment> segments = planner::SplitIntoSegments(
        predicted->at(i), free_navigation ? segment_m : 0.0,
        stops != input.stops.end() ? stops->second : std::vector<Eigen::Vector2d>{});
    const int action_first_step = static_cast<int>(steps.size());
    for (size_t j = 0; j < segments.size(); ++j) {
      const bool last = j + 1 == segments.size();
      schedule.whole_from.push_back(action_first_step);
      steps.push_back(
          {action, static_cast<int>(j), static_cast<int>(segments.size()), segments[j].gate});
      schedule.action_cells.push_back(sweep(segments[j].poses, load_m));
      // The load changes where the action ends (a trolley dock or an undock).
      schedule.action_end_cells.push_back(
          stand(segments[j].poses.back(), last ? load_after_m : load_m));
      schedule.action_start_s.push_back(t_s);
      t_s += segments[j].duration_s;
      if (segments[j].ends_at_stop) t_s += params_.step_aside_dwell_s;
    }
    load_m = load_after_m;
  }
  schedule.first_unfinished = skipped;
  // The action the robot may be in already (a later window, or a job resumed after a restart)
  // stays cleared whole; one whose way was planned again is cleared afresh, the robot standing.
  if (input.hold_under_way && input.hold_under_way->action_index == skipped) {
    schedule.cleared_up_to = FirstStepOf(steps, skipped) - 1;
    schedule.begun = true;
  } else if (skipped >= static_cast<int>(all.size())) {
    schedule.cleared_up_to = skipped - 1;
  } else if (skipped > 0 || input.resume_from_telemetry) {
    schedule.cleared_up_to = FirstStepOf(steps, skipped + 1) - 1;
  } else {
    schedule.cleared_up_to = -1;
  }
  out.schedule = std::move(schedule);
  return out;
}

}  // namespace fleetnav::server
