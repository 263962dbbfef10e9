#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/planner/grid/costmap.hpp"

namespace fleetnav::planner {

/// The connected regions of a costmap's cells where the footprint's inscribed circle fits (its
/// centre at least the inscribed radius, less half a cell, from every obstacle cell centre),
/// 4-connected, labelled once by a flood fill. Every pose a robot's footprint fits at lies in
/// such a cell, and every way it drives stays in them, so two places in different regions (or
/// one in none) cannot be joined by any path of the robot: a necessary condition for a way,
/// cheap to ask once labelled (a search would spend its whole time limit to find none). Points
/// are in the costmap's grid frame (metres from the grid's lower-left corner).
class FreeSpaceRegions {
 public:
  static constexpr int kNone = -1;

  explicit FreeSpaceRegions(const Costmap& costmap);
  /// The region of the cell containing `point_in_grid`; kNone outside the grid or where the
  /// inscribed circle does not fit.
  int RegionAt(const Eigen::Vector2d& point_in_grid) const;
  /// The region of the nearest cell within `within_m` of the point that has one (a robot
  /// parked closer to a wall than its padded inscribed circle still drives off from there);
  /// kNone when no such cell is that near.
  int RegionNear(const Eigen::Vector2d& point_in_grid, double within_m) const;
  /// Whether both points lie in the same region, each taken as in RegionNear.
  bool Connected(const Eigen::Vector2d& a_in_grid, const Eigen::Vector2d& b_in_grid,
                 double within_m = 0.0) const;
  int region_count() const { return region_count_; }

 private:
  int width_ = 0;
  int height_ = 0;
  double resolution_m_ = 0.0;
  int region_count_ = 0;
  std::vector<int32_t> region_;  ///< per cell, row-major; kNone where the circle does not fit
};

}  // namespace fleetnav::planner
