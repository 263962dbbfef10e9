#include "fleetnav/planner/coordination/route_prediction.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/angles.hpp"

namespace fleetnav::planner {
namespace {

/// Appends poses from `from` to `to` (excluding `from`), at most `step_m` apart, facing along
/// the line.
void AppendLine(std::vector<Pose2>& poses, const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                double step_m) {
  const Eigen::Vector2d d = to - from;
  const double length_m = d.norm();
  if (length_m < 1e-9) return;
  const double yaw = std::atan2(d.y(), d.x());
  const int steps = std::max(1, static_cast<int>(std::ceil(length_m / step_m)));
  for (int i = 1; i <= steps; ++i) {
    const Eigen::Vector2d p = from + d * (static_cast<double>(i) / steps);
    poses.emplace_back(p.x(), p.y(), yaw);
  }
}

/// Appends `path` (excluding its first pose) with poses in between, so that neighbours are at
/// most `step_m` and `yaw_step_rad` apart.
void AppendPoses(std::vector<Pose2>& poses, const std::vector<Pose2>& path, double step_m,
                 double yaw_step_rad) {
  for (size_t i = 1; i < path.size(); ++i) {
    const Pose2& a = path[i - 1];
    const Pose2& b = path[i];
    const double turn_rad = NormalizeAngle(b.yaw_rad() - a.yaw_rad());
    const int steps = std::max(
        {1, static_cast<int>(std::ceil((b.translation() - a.translation()).norm() / step_m)),
         static_cast<int>(std::ceil(std::abs(turn_rad) / yaw_step_rad))});
    for (int s = 1; s <= steps; ++s) {
      const double f = static_cast<double>(s) / steps;
      const Eigen::Vector2d p = a.translation() + f * (b.translation() - a.translation());
      poses.emplace_back(p.x(), p.y(), a.yaw_rad() + f * turn_rad);
    }
  }
}

/// Appends poses that keep `path`'s first `max_length_m` metres (all of it when <= 0).
double AppendPolyline(std::vector<Pose2>& poses, const std::vector<Eigen::Vector2d>& path,
                      double max_length_m, double step_m) {
  double length_m = 0.0;
  for (size_t i = 1; i < path.size(); ++i) {
    Eigen::Vector2d to = path[i];
    const double leg_m = (path[i] - path[i - 1]).norm();
    bool last = false;
    if (max_length_m > 0.0 && length_m + leg_m >= max_length_m) {
      to = path[i - 1] + (path[i] - path[i - 1]) * ((max_length_m - length_m) / leg_m);
      last = true;
    }
    AppendLine(poses, path[i - 1], to, step_m);
    length_m += (to - path[i - 1]).norm();
    if (last) break;
  }
  return length_m;
}

/// The pieces of a stripe as a path from the foot point of `from` onwards in the direction
/// of `from`'s heading: the pieces' end points beyond the foot point, nearest first.
std::vector<Eigen::Vector2d> StripePath(const std::vector<const StripeMarker*>& pieces,
                                        const Pose2& from) {
  const Eigen::Vector2d heading(std::cos(from.yaw_rad()), std::sin(from.yaw_rad()));
  const Eigen::Vector2d origin = from.translation();
  Eigen::Vector2d foot = origin;
  double nearest_m = std::numeric_limits<double>::infinity();
  std::vector<Eigen::Vector2d> ends;
  for (const StripeMarker* piece : pieces) {
    const Eigen::Vector2d along(std::cos(piece->yaw_rad), std::sin(piece->yaw_rad));
    const Eigen::Vector2d a = piece->position_m - along * piece->length_m / 2.0;
    const Eigen::Vector2d b = piece->position_m + along * piece->length_m / 2.0;
    ends.push_back(a);
    ends.push_back(b);
    const double t = std::clamp((origin - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    const Eigen::Vector2d candidate = a + t * (b - a);
    if ((candidate - origin).norm() < nearest_m) {
      nearest_m = (candidate - origin).norm();
      foot = candidate;
    }
  }
  const double foot_s = (foot - origin).dot(heading);
  std::vector<std::pair<double, Eigen::Vector2d>> ahead;
  for (const Eigen::Vector2d& end : ends) {
    const double s = (end - origin).dot(heading);
    if (s > foot_s + 1e-6) ahead.emplace_back(s, end);
  }
  std::sort(ahead.begin(), ahead.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<Eigen::Vector2d> path{origin, foot};
  for (const auto& [s, end] : ahead) {
    if ((end - path.back()).norm() > 1e-6) path.push_back(end);
  }
  return path;
}

std::vector<const StripeMarker*> Pieces(const MarkerSet* markers, MarkerKind kind, int stripe_id) {
  std::vector<const StripeMarker*> out;
  if (markers == nullptr) return out;
  for (const StripeMarker& m : markers->markers) {
    if (m.kind == kind && (stripe_id == 0 || m.stripe_id == stripe_id)) out.push_back(&m);
  }
  return out;
}

}  // namespace

absl::StatusOr<WaypointPath> PlanThroughWaypoints(
    SingleRobotPlanner& planner, const Pose2& map_origin, const Pose2& from,
    const std::vector<Eigen::Vector2d>& waypoints_m, const Pose2& goal, double time_limit_s,
    const std::vector<std::optional<double>>& waypoint_yaws_rad) {
  const Pose2 grid_from_map = map_origin.Inverse();
  // Legs: the robot → each waypoint → the goal; a waypoint faces the next point unless its yaw
  // is given, and then it is reached at that yaw.
  std::vector<Pose2> targets;
  std::vector<bool> fixed_yaw;
  for (size_t i = 0; i < waypoints_m.size(); ++i) {
    const Eigen::Vector2d next =
        i + 1 < waypoints_m.size() ? waypoints_m[i + 1] : goal.translation();
    const Eigen::Vector2d d = next - waypoints_m[i];
    const std::optional<double> yaw =
        i < waypoint_yaws_rad.size() ? waypoint_yaws_rad[i] : std::nullopt;
    targets.emplace_back(waypoints_m[i].x(), waypoints_m[i].y(),
                         yaw.value_or(std::atan2(d.y(), d.x())));
    fixed_yaw.push_back(yaw.has_value());
  }
  targets.push_back(goal);
  fixed_yaw.push_back(true);
  WaypointPath out;
  Pose2 leg_start = from;
  for (size_t t = 0; t < targets.size(); ++t) {
    PathRequest request;
    request.start = grid_from_map * leg_start;
    request.goal = grid_from_map * targets[t];
    request.time_limit_s = time_limit_s;
    request.goal_tolerance_rad = fixed_yaw[t] ? 0.1 : 0.8;
    absl::StatusOr<PathResult> leg = planner.Plan(request);
    if (!leg.ok()) {
      return absl::Status(leg.status().code(),
                          absl::StrFormat("no path to (%.2f, %.2f): %s", targets[t].x_m(),
                                          targets[t].y_m(), leg.status().message()));
    }
    if (!leg->exact) {
      return absl::NotFoundError(
          absl::StrFormat("(%.2f, %.2f) cannot be reached on the map from (%.2f, %.2f)",
                          targets[t].x_m(), targets[t].y_m(), leg_start.x_m(), leg_start.y_m()));
    }
    for (const Pose2& p : leg->poses) out.poses.push_back(map_origin * p);
    out.length_m += leg->length_m;
    leg_start = targets[t];
  }
  out.poses.push_back(goal);
  return out;
}

absl::StatusOr<std::vector<PredictedAction>> PredictRoute(const Route& route, const Pose2& start,
                                                          const MarkerSet* markers,
                                                          SingleRobotPlanner* planner,
                                                          const Pose2& map_origin,
                                                          const RoutePredictionParams& params) {
  std::vector<PredictedAction> out;
  Pose2 pose = start;
  for (size_t i = 0; i < route.actions.size(); ++i) {
    const RouteAction& action = route.actions[i];
    PredictedAction predicted;
    predicted.poses.push_back(pose);
    const Eigen::Vector2d heading(std::cos(pose.yaw_rad()), std::sin(pose.yaw_rad()));
    auto straight = [&](double distance_m, double speed_mps) {
      AppendLine(predicted.poses, pose.translation(), pose.translation() + heading * distance_m,
                 params.pose_step_m);
      // A straight keeps the heading even when it reverses.
      for (size_t p = 1; p < predicted.poses.size(); ++p) {
        predicted.poses[p] =
            Pose2(predicted.poses[p].x_m(), predicted.poses[p].y_m(), pose.yaw_rad());
      }
      predicted.duration_s = std::abs(distance_m) / std::max(speed_mps, 1e-3);
    };
    auto follow = [&](const std::vector<const StripeMarker*>& pieces, double distance_m,
                      double speed_mps) {
      const double length_m =
          AppendPolyline(predicted.poses, StripePath(pieces, pose), distance_m, params.pose_step_m);
      predicted.duration_s = length_m / std::max(speed_mps, 1e-3);
    };
    if (const auto* turn = std::get_if<TurnAction>(&action.params)) {
      const int steps =
          std::max(1, static_cast<int>(std::ceil(std::abs(turn->angle_rad) / params.yaw_step_rad)));
      for (int s = 1; s <= steps; ++s) {
        predicted.poses.emplace_back(pose.x_m(), pose.y_m(),
                                     pose.yaw_rad() + turn->angle_rad * s / steps);
      }
      predicted.duration_s = std::abs(turn->angle_rad) / std::max(turn->yaw_rate_radps, 1e-3);
    } else if (const auto* line = std::get_if<StraightAction>(&action.params)) {
      straight(line->distance_m, line->speed_mps);
    } else if (const auto* move = std::get_if<MoveAction>(&action.params)) {
      // Sideways or back, heading held.
      AppendLine(predicted.poses, pose.translation(), pose.TransformPoint({move->dx_m, move->dy_m}),
                 params.pose_step_m);
      for (Pose2& p : predicted.poses) p = Pose2(p.x_m(), p.y_m(), pose.yaw_rad());
      predicted.duration_s = std::hypot(move->dx_m, move->dy_m) / std::max(move->speed_mps, 1e-3);
    } else if (const auto* fence = std::get_if<FenceNavigationAction>(&action.params)) {
      straight(fence->distance_m, fence->speed_mps);
    } else if (const auto* stripe = std::get_if<StripeNavigationAction>(&action.params)) {
      std::vector<const StripeMarker*> pieces =
          Pieces(markers, MarkerKind::kFollowStripe, stripe->stripe_id);
      if (pieces.empty()) {
        return absl::InvalidArgumentError(
            absl::StrCat("actions[", i, "] (stripe_navigation): stripe ", stripe->stripe_id,
                         " is not in the marker set"));
      }
      const bool by_distance = action.end.kind == EndConditionKind::kDistance;
      follow(pieces, by_distance ? stripe->distance_m : 0.0, stripe->speed_mps);
    } else if (const auto* dock = std::get_if<DockAction>(&action.params)) {
      std::vector<const StripeMarker*> pieces = Pieces(markers, MarkerKind::kChargerStripe, 0);
      const TrolleyPlacement* trolley = dock->target == DockTarget::kTrolley && markers != nullptr
                                            ? markers->FindTrolley(dock->target_id)
                                            : nullptr;
      if (trolley != nullptr) {
        // To a point before the trolley's nearer end, then under it to its centre (about the
        // agent's approach and final dock frames), entered from the end the robot is nearer
        // (the trolley is symmetric).
        Pose2 facing = trolley->pose;
        const Eigen::Vector2d backwards = facing.TransformPoint({-1, 0}) - facing.translation();
        if (backwards.dot(pose.translation() - facing.translation()) < 0.0) {
          facing = facing * Pose2(0, 0, kPi);
        }
        const Eigen::Vector2d approach =
            facing.TransformPoint({-(0.5 * trolley->size_m.x() + params.trolley_approach_m), 0.0});
        const double length_m =
            AppendPolyline(predicted.poses, {pose.translation(), approach, facing.translation()},
                           0.0, params.pose_step_m);
        predicted.poses.push_back(facing);
        predicted.duration_s = length_m / params.trolley_dock_speed_mps + params.lift_s;
      } else if (pieces.empty()) {
        straight(params.default_dock_distance_m, 0.2);
      } else {
        follow(pieces, 0.0, 0.2);
      }
    } else if (std::holds_alternative<UndockAction>(action.params)) {
      predicted.poses.push_back(pose);  // standing while the lift goes down
      predicted.duration_s = params.lift_s;
    } else if (const auto* nav = std::get_if<FreeNavigationAction>(&action.params)) {
      if (planner != nullptr) {
        absl::StatusOr<WaypointPath> path =
            PlanThroughWaypoints(*planner, map_origin, pose, nav->waypoints_m, nav->goal,
                                 params.plan_time_limit_s, nav->waypoint_yaws_rad);
        if (!path.ok()) {
          return absl::Status(
              path.status().code(),
              absl::StrCat("actions[", i, "] (free_navigation): ", path.status().message()));
        }
        std::vector<Pose2> poses{pose};
        poses.insert(poses.end(), path->poses.begin(), path->poses.end());
        AppendPoses(predicted.poses, poses, params.pose_step_m, params.yaw_step_rad);
        predicted.duration_s = path->length_m / std::max(nav->speed_mps, 1e-3);
      } else {
        std::vector<Eigen::Vector2d> points{pose.translation()};
        points.insert(points.end(), nav->waypoints_m.begin(), nav->waypoints_m.end());
        points.push_back(nav->goal.translation());
        const double length_m = AppendPolyline(predicted.poses, points, 0.0, params.pose_step_m);
        predicted.duration_s = length_m / std::max(nav->speed_mps, 1e-3);
      }
      predicted.poses.push_back(nav->goal);
    }
    pose = predicted.poses.back();
    out.push_back(std::move(predicted));
  }
  return out;
}

}  // namespace fleetnav::planner
