#include "fleetnav/robot_agent/action_remainder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fleetnav::agent {
namespace {

constexpr double kLeftoverDistanceM = 0.01;
constexpr double kLeftoverAngleRad = 0.005;

/// The distance left of a leg whose distance_m bounds it (0: unbounded, nothing to scale).
/// nullopt when a leg that ends on its distance has nothing left.
std::optional<double> LegDistanceLeft(double distance_m, double fraction_done,
                                      EndConditionKind end) {
  if (distance_m <= 0.0) return distance_m;
  const double left_m = distance_m * (1.0 - fraction_done);
  if (end == EndConditionKind::kDistance) {
    if (left_m < kLeftoverDistanceM) return std::nullopt;
    return left_m;
  }
  return std::min(distance_m, left_m + kEndSlackM);
}

/// Squared distance from p to the segment a–b.
double SquaredDistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).squaredNorm();
}

/// The first waypoint still ahead of a robot at `position`: after the start of the segment of
/// waypoints…goal nearest to it. None is dropped while the robot is nearer the first waypoint
/// than any segment beyond it.
size_t FirstWaypointAhead(const FreeNavigationAction& nav, const Eigen::Vector2d& position) {
  std::vector<Eigen::Vector2d> points = nav.waypoints_m;
  points.push_back(nav.goal.translation());
  size_t nearest_segment = 0;
  double best = (position - points.front()).squaredNorm();
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const double d2 = SquaredDistanceToSegment(position, points[i], points[i + 1]);
    if (d2 < best) {
      best = d2;
      nearest_segment = i + 1;  // waypoints 0..i are behind
    }
  }
  return nearest_segment;
}

}  // namespace

std::optional<RouteAction> RemainderOf(const RouteAction& action, double fraction_done,
                                       const Pose2& pose_in_map) {
  const double done = std::clamp(fraction_done, 0.0, 1.0);
  RouteAction left = action;
  if (auto* turn = std::get_if<TurnAction>(&left.params)) {
    turn->angle_rad *= 1.0 - done;
    if (std::abs(turn->angle_rad) < kLeftoverAngleRad) return std::nullopt;
  } else if (auto* straight = std::get_if<StraightAction>(&left.params)) {
    straight->distance_m *= 1.0 - done;
    if (std::abs(straight->distance_m) < kLeftoverDistanceM) return std::nullopt;
  } else if (auto* move = std::get_if<MoveAction>(&left.params)) {
    move->dx_m *= 1.0 - done;
    move->dy_m *= 1.0 - done;
    if (std::hypot(move->dx_m, move->dy_m) < kLeftoverDistanceM) return std::nullopt;
  } else if (auto* fence = std::get_if<FenceNavigationAction>(&left.params)) {
    const std::optional<double> d = LegDistanceLeft(fence->distance_m, done, left.end.kind);
    if (!d) return std::nullopt;
    fence->distance_m = *d;
  } else if (auto* stripe = std::get_if<StripeNavigationAction>(&left.params)) {
    const std::optional<double> d = LegDistanceLeft(stripe->distance_m, done, left.end.kind);
    if (!d) return std::nullopt;
    stripe->distance_m = *d;
  } else if (auto* nav = std::get_if<FreeNavigationAction>(&left.params)) {
    const auto behind =
        static_cast<std::ptrdiff_t>(FirstWaypointAhead(*nav, pose_in_map.translation()));
    nav->waypoints_m.erase(nav->waypoints_m.begin(), nav->waypoints_m.begin() + behind);
    if (!nav->waypoint_yaws_rad.empty()) {
      nav->waypoint_yaws_rad.erase(nav->waypoint_yaws_rad.begin(),
                                   nav->waypoint_yaws_rad.begin() + behind);
    }
  }
  return left;
}

}  // namespace fleetnav::agent
