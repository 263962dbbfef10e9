#include "fleetnav/robot_agent/control/modes/free_navigation_controller.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/segment_gate.hpp"
#include "fleetnav/planner/coordination/route_prediction.hpp"
#include "fleetnav/planner/grid/body_clearance.hpp"
#include "fleetnav/robot_agent/scan_features.hpp"

namespace fleetnav::agent {
namespace {

/// Stops the robot and ends the action with `failure`.
ControlOutput Failed(ControlOutput out, absl::Status failure) {
  out.command = Twist2{};
  out.failure = std::move(failure);
  return out;
}

planner::CostmapParams CostmapParamsFor(double padding_m) {
  planner::CostmapParams p;
  p.padding_m = padding_m;
  return p;
}

}  // namespace

absl::Status FreeNavigationParams::Validate() const {
  if (absl::Status s = tracker.Validate(); !s.ok()) return s;
  if (absl::Status s = holonomic.Validate(); !s.ok()) return s;
  if (absl::Status s = smoothing.Validate(); !s.ok()) return s;
  if (absl::Status s = ackermann.Validate(); !s.ok()) return s;
  if (absl::Status s = unmapped.Validate(); !s.ok()) return s;
  if (!(std::isfinite(goal_check_m) && goal_check_m > 0.0 && std::isfinite(goal_check_rad) &&
        goal_check_rad > 0.0 && max_goal_corrections >= 0)) {
    return absl::InvalidArgumentError(
        "goal_check_m > 0, goal_check_rad > 0, max_goal_corrections >= 0 required");
  }
  if (!(std::isfinite(padding_m) && padding_m >= 0.0 && std::isfinite(plan_time_limit_s) &&
        plan_time_limit_s > 0.0 && std::isfinite(replan_cross_track_m) &&
        replan_cross_track_m > 0.0 && std::isfinite(blocked_timeout_s) && blocked_timeout_s > 0.0 &&
        max_replans_in_window > 0 && std::isfinite(replan_window_s) && replan_window_s > 0.0 &&
        std::isfinite(obstructed_replan_interval_s) && obstructed_replan_interval_s >= 0.0)) {
    return absl::InvalidArgumentError(
        "padding_m >= 0, plan_time_limit_s > 0, replan_cross_track_m > 0, blocked_timeout_s > 0, "
        "max_replans_in_window > 0, replan_window_s > 0, obstructed_replan_interval_s >= 0 "
        "required");
  }
  return absl::OkStatus();
}

namespace {

/// Sets the cells of `grid` whose centres lie in `box_in_base` placed at `base_in_map` to
/// `value`.
void SetCellsIn(const Eigen::AlignedBox2d& box_in_base, const Pose2& base_in_map, int8_t value,
                OccupancyGrid* grid) {
  const Pose2 base_from_map = base_in_map.Inverse();
  const double r = box_in_base.diagonal().norm() * 0.5 + grid->resolution_m();
  const Eigen::Vector2d c = base_in_map.TransformPoint(box_in_base.center());
  const std::optional<CellIndex> lo = grid->WorldToCell(c - Eigen::Vector2d(r, r));
  const std::optional<CellIndex> hi = grid->WorldToCell(c + Eigen::Vector2d(r, r));
  const int x0 = lo ? lo->x : 0, y0 = lo ? lo->y : 0;
  const int x1 = hi ? hi->x : grid->width() - 1;
  const int y1 = hi ? hi->y : grid->height() - 1;
  for (int y = std::max(0, y0); y <= y1; ++y) {
    for (int x = std::max(0, x0); x <= x1; ++x) {
      const CellIndex cell{x, y};
      if (!grid->InBounds(cell)) continue;
      if (box_in_base.contains(base_from_map.TransformPoint(grid->CellToWorld(cell)))) {
        grid->SetValue(cell, value);
      }
    }
  }
}

/// How far beyond a lifted trolley's outline its cells are freed: the map marks every cell its
/// legs (standing at the outline's corners) touch, up to half a cell diagonal outside it, and
/// the robot that lifted it stands up to a few centimetres and degrees off its centre.
double LoadMargin(const OccupancyGrid& grid) { return 2.0 * grid.resolution_m(); }

void FreeCellsIn(const Eigen::AlignedBox2d& box_in_base, const Pose2& base_in_map,
                 OccupancyGrid* grid) {
  SetCellsIn(box_in_base, base_in_map, OccupancyGrid::kFreeValue, grid);
}

void FillCellsIn(const Eigen::AlignedBox2d& box_in_base, const Pose2& base_in_map,
                 OccupancyGrid* grid) {
  SetCellsIn(box_in_base, base_in_map, OccupancyGrid::kOccupiedValue, grid);
}

}  // namespace

void MovedLoads::Lifted(const Pose2& pose_in_map, const Eigen::Vector2d& size_m) {
  std::erase_if(set_down_at, [&](const LoadOutline& placed) {
    return (placed.pose_in_map.translation() - pose_in_map.translation()).norm() <
           0.5 * placed.size_m.minCoeff();
  });
  lifted_from.push_back({pose_in_map, size_m});
}

void MovedLoads::SetDown(const Pose2& pose_in_map, const Eigen::Vector2d& size_m) {
  set_down_at.push_back({pose_in_map, size_m});
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
                                                   FreeNavigationParams params, bool carrying,
                                                   MovedLoads moved)
    : action_(action),
      model_(model),
      map_(std::move(map)),
      params_(params),
      unmapped_(map_, params.unmapped),
      carrying_(carrying),
      moved_(std::move(moved)) {
  if (model.kinematics == Kinematics::kOmnidirectional) {
    HolonomicTrackerParams p = params.holonomic;
    p.desired_speed_mps = action.speed_mps;
    tracker_ = std::make_unique<HolonomicTracker>(p, model.limits);
  } else if (model.kinematics == Kinematics::kAckermann) {
    AckermannPurePursuitParams p = params.ackermann;
    p.desired_speed_mps = action.speed_mps;
    auto car = std::make_unique<AckermannPurePursuit>(p, model);
    car_tracker_ = car.get();
    tracker_ = std::move(car);
  } else {
    RegulatedPurePursuitParams p = params.tracker;
    p.desired_speed_mps = action.speed_mps;
    tracker_ = std::make_unique<RegulatedPurePursuit>(p, model.limits);
  }
}

bool FreeNavigationController::AvoidsUnmappedObstacles() const {
  return model_.kinematics == Kinematics::kAckermann && params_.ackermann.avoid_obstacles;
}

absl::Status FreeNavigationController::BuildPlanner(const Pose2& from_in_map) {
  OccupancyGrid grid = *map_;
  marked_cells_ = 0;
  if (carrying_) {
    if (!carried_from_in_map_) carried_from_in_map_ = from_in_map;
    Eigen::AlignedBox2d load = model_.FootprintBounds();
    load.min().array() -= LoadMargin(grid);
    load.max().array() += LoadMargin(grid);
    FreeCellsIn(load, *carried_from_in_map_, &grid);
  }
  for (const LoadOutline& lifted : moved_.lifted_from) {
    const Eigen::Vector2d half_m =
        0.5 * lifted.size_m + Eigen::Vector2d::Constant(LoadMargin(grid));
    FreeCellsIn(Eigen::AlignedBox2d(-half_m, half_m), lifted.pose_in_map, &grid);
  }
  for (const LoadOutline& set_down : moved_.set_down_at) {
    const Eigen::Vector2d half_m = 0.5 * set_down.size_m;
    const Eigen::AlignedBox2d outline(-half_m, half_m);
    if (outline.contains(
            set_down.pose_in_map.Inverse().TransformPoint(from_in_map.translation()))) {
      continue;  // the robot is still under it
    }
    FillCellsIn(outline, set_down.pose_in_map, &grid);
  }
  if (AvoidsUnmappedObstacles()) {
    // What the laser has seen and the map does not show, except under the robot and its
    // padding (where it would put the start in collision; VFH+ keeps the robot off that).
    Eigen::AlignedBox2d keep_clear = model_.FootprintBounds();
    const double margin_m = params_.padding_m + grid.resolution_m();
    keep_clear.min().array() -= margin_m;
    keep_clear.max().array() += margin_m;
    marked_cells_ = unmapped_.MarkOn(grid, from_in_map, keep_clear);
  }
  absl::StatusOr<planner::Costmap> costmap =
      planner::Costmap::Build(grid, model_.footprint_m, CostmapParamsFor(params_.padding_m));
  if (!costmap.ok()) return costmap.status();
  planner_.reset();
  costmap_.emplace(*std::move(costmap));
  absl::StatusOr<std::unique_ptr<planner::SingleRobotPlanner>> planner =
      planner::MakeSingleRobotPlanner(&*costmap_, model_, planner::NavigationPlannerParams(model_));
  if (!planner.ok()) return planner.status();
  planner_ = *std::move(planner);
  return absl::OkStatus();
}

absl::Status FreeNavigationController::Plan(const Pose2& from_in_map) {
  // A costmap with marks is rebuilt too: what they marked may have been cleared since.
  if (!costmap_ || (AvoidsUnmappedObstacles() && (unmapped_.size() > 0 || marked_cells_ > 0))) {
    if (absl::Status s = BuildPlanner(from_in_map); !s.ok()) return s;
  }
  const std::vector<Eigen::Vector2d> ahead(action_.waypoints_m.begin() + next_waypoint_,
                                           action_.waypoints_m.end());
  std::vector<std::optional<double>> yaws_ahead;
  for (size_t i = next_waypoint_; i < action_.waypoints_m.size(); ++i) {
    yaws_ahead.push_back(action_.WaypointYaw(i));
  }
  absl::StatusOr<planner::WaypointPath> path =
      planner::PlanThroughWaypoints(*planner_, map_->origin(), from_in_map, ahead, action_.goal,
                                    params_.plan_time_limit_s, yaws_ahead);
  if (!path.ok() && marked_cells_ > 0) {
    return absl::Status(path.status().code(),
                        absl::StrCat(path.status().message(),
                                     " (round the obstacles the laser has seen: ", marked_cells_,
                                     " cells the map shows free)"));
  }
  if (!path.ok()) return path.status();
  planned_length_m_ = path->length_m;
  last_plan_s_ = elapsed_s_;
  if (model_.kinematics == Kinematics::kOmnidirectional) path->poses = Smoothed(path->poses);
  std::vector<double> clearances_m;
  if (model_.kinematics == Kinematics::kAckermann) clearances_m = ClearancesAlong(path->poses);
  tracker_->SetPath(std::move(path->poses));
  if (car_tracker_ != nullptr) car_tracker_->SetClearances(std::move(clearances_m));
  planned_ = true;
  return absl::OkStatus();
}

std::vector<double> FreeNavigationController::ClearancesAlong(
    const std::vector<Pose2>& path_in_map) const {
  const planner::BodyClearance clearance(&*costmap_, model_.footprint_m);
  const Pose2 grid_from_map = map_->origin().Inverse();
  std::vector<double> clearances_m;
  clearances_m.reserve(path_in_map.size());
  for (const Pose2& p : path_in_map) clearances_m.push_back(clearance.At(grid_from_map * p));
  return clearances_m;
}

std::vector<Pose2> FreeNavigationController::Smoothed(const std::vector<Pose2>& path_in_map) {
  const Pose2 grid_from_map = map_->origin().Inverse();
  planner::PathResult in_grid;
  for (const Pose2& p : path_in_map) in_grid.poses.push_back(grid_from_map * p);
  absl::StatusOr<planner::Trajectory> smooth =
      planner::SmoothPath(in_grid, &*costmap_, model_, params_.smoothing);
  // SmoothPath falls back to the planner's own motion where the spline collides; it fails
  // only on input it cannot take, and then the planner's path is followed as it is.
  if (!smooth.ok() || smooth->points.empty()) return path_in_map;
  std::vector<Pose2> out;
  out.reserve(smooth->points.size() + 1);
  for (const planner::TrajectoryPoint& point : smooth->points) {
    out.push_back(map_->origin() *
                  Pose2(point.position_m.x(), point.position_m.y(), point.yaw_rad));
  }
  out.push_back(path_in_map.back());
  return out;
}

void FreeNavigationController::PassObstacles(const ControlInput& input) {
  if (!AvoidsUnmappedObstacles()) return;
  if (input.perception.laser) {
    // Only what the map does not explain: the planner has already gone round the rest.
    scan_points_in_base_ = unmapped_.AddScan(*input.perception.laser,
                                             input.perception.laser_in_base, input.pose_in_map);
    scan_pose_in_odom_ = input.pose_in_odom;
  }
  const Pose2 now_from_scan = input.pose_in_odom.Inverse() * scan_pose_in_odom_;
  std::vector<Eigen::Vector2d> points;
  points.reserve(scan_points_in_base_.size());
  for (const Eigen::Vector2d& p : scan_points_in_base_) {
    points.push_back(now_from_scan.TransformPoint(p));
  }
  tracker_->SetObstacles(std::move(points));
}

std::optional<double> FreeNavigationController::PathDistanceToGate(const Pose2& gate) const {
  if (!planned_) return std::nullopt;
  return fleetnav::PathDistanceToGate(gate, tracker_->path_ahead());
}

ControlOutput FreeNavigationController::Step(const ControlInput& input) {
  ControlOutput out;
  out.mode = NavigationMode::kFreeNavigation;
  elapsed_s_ += input.dt_s;
  PassObstacles(input);
  if (!planned_) {
    if (absl::Status s = Plan(input.pose_in_map); !s.ok()) return Failed(std::move(out), s);
  }
  // Waypoints count as passed within a metre.
  while (next_waypoint_ < action_.waypoints_m.size() &&
         (action_.waypoints_m[next_waypoint_] - input.pose_in_map.translation()).norm() < 1.0) {
    ++next_waypoint_;
  }
  out.command = tracker_->Step(input.pose_in_map, input.dt_s);
  blocked_s_ = tracker_->blocked() ? blocked_s_ + input.dt_s : 0.0;
  if (blocked_s_ > params_.blocked_timeout_s) {
    return Failed(std::move(out),
                  absl::FailedPreconditionError(absl::StrFormat(
                      "obstacles not on the map block every direction ahead for "
                      "%.1f s at (%.2f, %.2f)",
                      blocked_s_, input.pose_in_map.x_m(), input.pose_in_map.y_m())));
  }
  const bool obstructed = tracker_->path_obstructed() &&
                          elapsed_s_ - last_plan_s_ >= params_.obstructed_replan_interval_s;
  if (obstructed || tracker_->cross_track_m() > params_.replan_cross_track_m) {
    std::erase_if(replans_at_s_,
                  [&](double t) { return t < elapsed_s_ - params_.replan_window_s; });
    replans_at_s_.push_back(elapsed_s_);
    if (static_cast<int>(replans_at_s_.size()) > params_.max_replans_in_window) {
      return Failed(std::move(out),
                    absl::AbortedError(absl::StrFormat(
                        "left the planned path %d times within %.0f s (obstacles not on the map?): "
                        "stopped at (%.2f, %.2f)",
                        static_cast<int>(replans_at_s_.size()), params_.replan_window_s,
                        input.pose_in_map.x_m(), input.pose_in_map.y_m())));
    }
    out.mode_reason =
        obstructed
            ? std::string("an obstacle not on the map stands on the path: replanning round it")
            : absl::StrFormat("off the path by %.2f m: replanning", tracker_->cross_track_m());
    if (absl::Status s = Plan(input.pose_in_map); !s.ok()) return Failed(std::move(out), s);
    out.command = tracker_->Step(input.pose_in_map, input.dt_s);
  }
  out.done = tracker_->done();
  if (out.done && goal_corrections_ < params_.max_goal_corrections &&
      !input.pose_in_map.IsNear(action_.goal, params_.goal_check_m, params_.goal_check_rad)) {
    ++goal_corrections_;
    const Pose2 error = action_.goal.Inverse() * input.pose_in_map;
    out.mode_reason = absl::StrFormat("ended %.2f m and %.1f deg from the goal: correcting",
                                      error.translation().norm(), RadToDeg(error.yaw_rad()));
    if (absl::Status s = Plan(input.pose_in_map); !s.ok()) return Failed(std::move(out), s);
    out.command = tracker_->Step(input.pose_in_map, input.dt_s);
    out.done = tracker_->done();
  }
  out.progress_fraction =
      planned_length_m_ > 0.0
          ? std::clamp(1.0 - tracker_->remaining_m() / planned_length_m_, 0.0, 1.0)
          : 0.0;
  if (out.done) {
    out.command = Twist2{};
    out.progress_fraction = 1.0;
  }
  return out;
}

}  // namespace fleetnav::agent
