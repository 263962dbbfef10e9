#include "fleetnav/robot_agent/free_navigation_controller.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/planner/route_prediction.hpp"

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
  const std::vector<Eigen::Vector2d> ahead(action_.waypoints_m.begin() + next_waypoint_,
                                           action_.waypoints_m.end());
  absl::StatusOr<planner::WaypointPath> path = planner::PlanThroughWaypoints(
      *planner_, map_->origin(), from_in_map, ahead, action_.goal, params_.plan_time_limit_s);
  if (!path.ok()) return path.status();
  planned_length_m_ = path->length_m;
  tracker_.SetPath(std::move(path->poses));
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
