#pragma once

#include <cstddef>
#include <vector>

#include "fleetnav/core/pose2.hpp"

namespace fleetnav::agent {

/// Along-path distance from each pose of `path` to its last pose (0 for the last).
std::vector<double> DistancesToGoal(const std::vector<Pose2>& path);

/// The index of the pose of path[first, last) nearest to `pose` (first on ties), and its
/// distance: the path trackers search forward from where the robot was last.
struct ClosestPose {
  size_t index = 0;
  double distance_m = 0.0;
};
ClosestPose FindClosestPose(const std::vector<Pose2>& path, const Pose2& pose, size_t first,
                            size_t last);

}  // namespace fleetnav::agent
