#pragma once

#include <Eigen/Core>
#include <vector>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/planner/grid/costmap.hpp"

namespace fleetnav::planner {

/// The distance from a robot's body to the nearest obstacle, estimated from the costmap's
/// distance field: the body's bounding box is cut along its long axis into pieces at most half
/// as long as it is wide, each covered by the disc round it, and the clearance is the least
/// distance from a disc centre to an obstacle cell less the disc's radius. It never overstates the
/// clearance (the discs cover the body); it understates it beside the body by a few centimetres and
/// ahead and behind by up to the radius less half a piece. Poses are in the costmap's grid
/// frame. Holds a pointer to the costmap, which must outlive it.
class BodyClearance {
 public:
  BodyClearance(const Costmap* costmap, const std::vector<Eigen::Vector2d>& footprint_m);
  /// Clearance in metres (≤ 0 touching; large far from everything).
  double At(const Pose2& pose_in_grid) const;

 private:
  const Costmap* costmap_;
  std::vector<Eigen::Vector2d> centres_in_base_;
  double radius_m_ = 0.0;
};

}  // namespace fleetnav::planner
