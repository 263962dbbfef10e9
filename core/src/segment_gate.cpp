#include "fleetnav/core/segment_gate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fleetnav {

double DistanceBeforeGate(const Pose2& gate, const Eigen::Vector2d& position_m) {
  const Eigen::Vector2d direction(std::cos(gate.yaw_rad()), std::sin(gate.yaw_rad()));
  return (gate.translation() - position_m).dot(direction);
}

bool ReachedGate(const Pose2& gate, const Eigen::Vector2d& position_m, double tolerance_m,
                 double reach_m, double turn_reach_m) {
  const double to_point_m = (gate.translation() - position_m).norm();
  return to_point_m <= turn_reach_m ||
         (to_point_m <= reach_m && DistanceBeforeGate(gate, position_m) <= tolerance_m);
}

double SpeedLimitBeforeGate(const Pose2& gate, const Eigen::Vector2d& position_m,
                            const Eigen::Vector2d& velocity_in_map_mps, double decel_mps2,
                            double stop_before_m, double approach_m) {
  const Eigen::Vector2d direction(std::cos(gate.yaw_rad()), std::sin(gate.yaw_rad()));
  if ((gate.translation() - position_m).norm() > approach_m ||
      velocity_in_map_mps.dot(direction) <= 0.0) {
    return std::numeric_limits<double>::max();
  }
  const double room_m = std::max(0.0, DistanceBeforeGate(gate, position_m) - stop_before_m);
  return std::sqrt(2.0 * decel_mps2 * room_m);
}

std::optional<double> PathDistanceToGate(const Pose2& gate, std::span<const Pose2> path_ahead,
                                         double stop_before_m, double reach_m,
                                         double turn_reach_m) {
  const Eigen::Vector2d direction(std::cos(gate.yaw_rad()), std::sin(gate.yaw_rad()));
  const auto short_of_line_m = [&](const Eigen::Vector2d& p) {
    return DistanceBeforeGate(gate, p) - stop_before_m;
  };
  const auto to_point_m = [&](const Eigen::Vector2d& p) { return (gate.translation() - p).norm(); };
  // Only where the path drives the gate's way: a way out and back passes its return's gates
  // going the other way.
  const auto gates_way = [&](size_t i) {
    return (path_ahead[i].translation() - path_ahead[i - 1].translation()).dot(direction) > 0.0;
  };
  if (path_ahead.size() >= 2 && gates_way(1) &&
      short_of_line_m(path_ahead[0].translation()) <= 0.0 &&
      to_point_m(path_ahead[0].translation()) <= reach_m) {
    return 0.0;  // there already
  }
  double along_m = 0.0;
  bool approached = false;  // within turn_reach_m of the gate's point, driving its way
  double closest_m = std::numeric_limits<double>::max();
  double closest_along_m = 0.0;
  for (size_t i = 1; i < path_ahead.size(); ++i) {
    const Eigen::Vector2d a = path_ahead[i - 1].translation();
    const Eigen::Vector2d b = path_ahead[i].translation();
    const double step_m = (b - a).norm();
    const bool drives_gates_way = gates_way(i);
    const double before_a = short_of_line_m(a);
    const double before_b = short_of_line_m(b);
    if (drives_gates_way && before_a > 0.0 && before_b <= 0.0) {
      const double t = before_a / (before_a - before_b);
      if (to_point_m(a + t * (b - a)) <= reach_m) return along_m + t * step_m;
    }
    along_m += step_m;
    const double to_b_m = to_point_m(b);
    if (drives_gates_way && to_b_m <= turn_reach_m) approached = true;
    if (!approached) continue;
    if (to_b_m > turn_reach_m) break;  // it turned away before the line
    if (to_b_m < closest_m) {
      closest_m = to_b_m;
      closest_along_m = along_m;
    }
  }
  if (!approached) return std::nullopt;
  return closest_along_m;
}

}  // namespace fleetnav
