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
                 double reach_m) {
  return (gate.translation() - position_m).norm() <= reach_m &&
         DistanceBeforeGate(gate, position_m) <= tolerance_m;
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

}  // namespace fleetnav
