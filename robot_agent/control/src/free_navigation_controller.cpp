#include "fleetnav/robot_agent/free_navigation_controller.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {
namespace {

planner::CostmapParams CostmapParamsFor(double padding_m) {
  planner::CostmapParams p;
  p.padding_m = padding_m;
  return p;
}

}  // namespace

absl::Status FreeNavigationParams::Validate() const {
  if (absl::Status s = tracker.Validate(); !s.ok()) return s;
  if (absl::Status s = lattice.Validate(); !s.ok()) return s;
  if (!(std::isfinite(padding_m) && padding_m >= 0.0 && std::isfinite(plan_time_limit_s) &&
        plan_time_limit_s > 0.0 && std::isfinite(replan_cross_track_m) &&
        replan_cross_track_m > 0.0)) {
    return absl::InvalidArgumentError(
        "padding_m >= 0, plan_time_limit_s > 0, replan_cross_track_m > 0 required");
  }
  return absl::OkStatus();
}

absl::Status CheckFreeNavigation(const FreeNavigationAction& action, const RobotModel& model,
                                 const OccupancyGrid& map, double padding_m) {
  absl::StatusOr<planner::Costmap> costmap =
      planner::Costmap::Build(map, model.footprint_m, CostmapParamsFor(padding_m));
  if (!costmap.ok()) return costmap.status();
  const Pose2 grid_from_map = map.origin().Inverse();
  const auto free = [&](const Pose2& pose_in_map) {
    const Pose2 p = grid_from_map * pose_in_map;
    return costmap->PoseFree(p.x_m(), p.y_m(), p.yaw_rad());
  };
  if (!free(action.goal)) {
    return absl::InvalidArgumentError(
        absl::StrFormat("goal (%.2f, %.2f) is not free for the robot's footprint on the map",
                        action.goal.x_m(), action.goal.y_m()));
  }
  for (size_t i = 0; i < action.waypoints_m.size(); ++i) {
    // A waypoint is passed at some heading: it must be free at one of them.
    bool any = false;
    for (int k = 0; k < 16 && !any; ++k) {
      any = free(Pose2(action.waypoints_m[i].x(), action.waypoints_m[i].y(), k * kPi / 8.0));
    }
    if (!any) {
      return absl::InvalidArgumentError(absl::StrFormat(
          "waypoints[%d] (%.2f, %.2f) is not free for the robot's footprint on the map",
          static_cast<int>(i), action.waypoints_m[i].x(), action.waypoints_m[i].y()));
    }
  }
  return absl::OkStatus();
}

FreeNavigationController::FreeNavigationController(const FreeNavigationAction& action,
                                                   const RobotModel& model,
                                                   std::shared_ptr<const OccupancyGrid> map,
                                                   FreeNavigationParams params)
    : action_(action),
      model_(model),
      map_(std::move(map)),
      params_(params),
      tracker_(
          [&] {
            RegulatedPurePursuitParams p = params.tracker;
            p.desired_speed_mps = action.speed_mps;
            return p;
          }(),
          model.limits) {}

absl::Status FreeNavigationController::Plan(const Pose2& from_in_map) {
  if (!costmap_) {
    absl::StatusOr<planner::Costmap> costmap =
        planner::Costmap::Build(*map_, model_.footprint_m, CostmapParamsFor(params_.padding_m));
    if (!costmap.ok()) return costmap.status();
    costmap_.emplace(*std::move(costmap));
    absl::StatusOr<std::unique_ptr<planner::SingleRobotPlanner>> planner =
        planner::MakeSingleRobotPlanner(&*costmap_, model_, params_.lattice);
    if (!planner.ok()) return planner.status();
    planner_ = *std::move(planner);
  }
  const Pose2 grid_from_map = map_->origin().Inverse();
  // Legs: the robot → each waypoint still ahead → the goal; waypoints face the next point.
  std::vector<Pose2> targets;
  for (size_t i = next_waypoint_; i < action_.waypoints_m.size(); ++i) {
    const Eigen::Vector2d next = i + 1 < action_.waypoints_m.size() ? action_.waypoints_m[i + 1]
                                                                    : action_.goal.translation();
    const Eigen::Vector2d d = next - action_.waypoints_m[i];
    targets.emplace_back(action_.waypoints_m[i].x(), action_.waypoints_m[i].y(),
                         std::atan2(d.y(), d.x()));
  }
  targets.push_back(action_.goal);
  std::vector<Pose2> path;
  Pose2 from = from_in_map;
  planned_length_m_ = 0.0;
  for (size_t t = 0; t < targets.size(); ++t) {
    planner::PathRequest request;
    request.start = grid_from_map * from;
    request.goal = grid_from_map * targets[t];
    request.time_limit_s = params_.plan_time_limit_s;
    const bool last = t + 1 == targets.size();
    // Waypoints are passed through, not stopped at: any heading within 45° will do.
    request.goal_tolerance_rad = last ? 0.1 : 0.8;
    absl::StatusOr<planner::PathResult> leg = planner_->Plan(request);
    if (!leg.ok()) {
      return absl::Status(leg.status().code(),
                          absl::StrFormat("no path to (%.2f, %.2f): %s", targets[t].x_m(),
                                          targets[t].y_m(), leg.status().message()));
    }
    if (!leg->exact) {
      return absl::NotFoundError(
          absl::StrFormat("(%.2f, %.2f) cannot be reached on the map from (%.2f, %.2f)",
                          targets[t].x_m(), targets[t].y_m(), from.x_m(), from.y_m()));
    }
    for (const Pose2& p : leg->poses) path.push_back(map_->origin() * p);
    planned_length_m_ += leg->length_m;
    from = targets[t];
  }
  path.push_back(action_.goal);
  tracker_.SetPath(std::move(path));
  planned_ = true;
  return absl::OkStatus();
}

ControlOutput FreeNavigationController::Step(const ControlInput& input) {
  ControlOutput out;
  out.mode = NavigationMode::kFreeNavigation;
  if (!planned_) {
    if (absl::Status s = Plan(input.pose_in_map); !s.ok()) {
      out.failure = s;
      return out;
    }
  }
  // Waypoints count as passed within a metre.
  while (next_waypoint_ < action_.waypoints_m.size() &&
         (action_.waypoints_m[next_waypoint_] - input.pose_in_map.translation()).norm() < 1.0) {
    ++next_waypoint_;
  }
  out.command = tracker_.Step(input.pose_in_map, input.dt_s);
  if (tracker_.cross_track_m() > params_.replan_cross_track_m) {
    out.mode_reason =
        absl::StrFormat("off the path by %.2f m: replanning", tracker_.cross_track_m());
    if (absl::Status s = Plan(input.pose_in_map); !s.ok()) {
      out.failure = s;
      return out;
    }
    out.command = tracker_.Step(input.pose_in_map, input.dt_s);
  }
  out.done = tracker_.done();
  out.progress_fraction =
      planned_length_m_ > 0.0
          ? std::clamp(1.0 - tracker_.remaining_m() / planned_length_m_, 0.0, 1.0)
          : 0.0;
  if (out.done) {
    out.command = Twist2{};
    out.progress_fraction = 1.0;
  }
  return out;
}

}  // namespace fleetnav::agent
