#include "fleetnav/robot_agent/stop_guard.hpp"

#include <algorithm>
#include <cmath>

namespace fleetnav::agent {
namespace {

bool ZoneStopOn(const RobotStop& stop, const std::string& map_id) {
  return !stop.whole_fleet() && stop.map_id == map_id && stop.polygon_in_map.size() >= 3;
}

double DistanceToZone(const Polygon2& zone, const Eigen::Vector2d& point) {
  return PolygonContains(zone, point) ? 0.0 : DistanceToPolygonBoundary(zone, point);
}

}  // namespace

Twist2 KeepOffStoppedZones(const Twist2& command, const std::vector<RobotStop>& stops,
                           const std::string& map_id, const Pose2& pose_in_map, double reach_m,
                           double braking_decel_mps2, double horizon_s) {
  const Eigen::Vector2d center = pose_in_map.translation();
  const double c = std::cos(pose_in_map.yaw_rad());
  const double s = std::sin(pose_in_map.yaw_rad());
  const Eigen::Vector2d moved =
      center + horizon_s * Eigen::Vector2d(c * command.vx_mps - s * command.vy_mps,
                                           s * command.vx_mps + c * command.vy_mps);
  double scale = 1.0;
  for (const RobotStop& stop : stops) {
    if (!ZoneStopOn(stop, map_id)) continue;
    const double distance_m = DistanceToZone(stop.polygon_in_map, center);
    const double nearing_mps =
        (distance_m - DistanceToZone(stop.polygon_in_map, moved)) / horizon_s;
    if (nearing_mps <= 0.0) continue;
    const double allowed_mps =
        std::sqrt(2.0 * braking_decel_mps2 * std::max(0.0, distance_m - reach_m));
    scale = std::min(scale, allowed_mps / nearing_mps);
  }
  if (scale >= 1.0) return command;
  return Twist2{command.vx_mps * scale, command.vy_mps * scale, command.yaw_rate_radps * scale};
}

}  // namespace fleetnav::agent
