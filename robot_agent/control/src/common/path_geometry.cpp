#include "fleetnav/robot_agent/control/common/path_geometry.hpp"

#include <algorithm>
#include <limits>

namespace fleetnav::agent {

std::vector<double> DistancesToGoal(const std::vector<Pose2>& path) {
  std::vector<double> to_goal_m(path.size(), 0.0);
  for (size_t i = path.size(); i-- > 1;) {
    to_goal_m[i - 1] = to_goal_m[i] + (path[i].translation() - path[i - 1].translation()).norm();
  }
  return to_goal_m;
}

ClosestPose FindClosestPose(const std::vector<Pose2>& path, const Pose2& pose, size_t first,
                            size_t last) {
  ClosestPose closest{first, std::numeric_limits<double>::infinity()};
  for (size_t i = first; i < std::min(last, path.size()); ++i) {
    const double d = (path[i].translation() - pose.translation()).norm();
    if (d < closest.distance_m) closest = {i, d};
  }
  return closest;
}

}  // namespace fleetnav::agent
