#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <unordered_set>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/sensor_frame.hpp"

namespace fleetnav::agent {

struct UnmappedObstaclesParams {
  /// A return within this distance of an obstacle on the map is that obstacle (the pose
  /// estimate is a few centimetres off); farther ones are obstacles the map does not show.
  double explained_by_map_m = 0.2;
  /// Beams clear the cells they pass through out to this range.
  double clearing_range_m = 8.0;
  absl::Status Validate() const;
};

/// What the laser has seen that the map does not show, in the map's cells — the obstacle layer
/// of a layered costmap (Lu, Hershberger & Smart, "Layered Costmaps for Context-Sensitive
/// Navigation", IROS 2014): each scan first clears the cells its beams pass through (so a robot
/// or person that has walked on is forgotten), then marks the cells of its returns that the map
/// does not explain. Cells stay marked until a later beam passes through them, so what a car's
/// forward laser has driven past is still known when it reverses. Not thread-safe.
class UnmappedObstacles {
 public:
  UnmappedObstacles(std::shared_ptr<const OccupancyGrid> map, UnmappedObstaclesParams params);

  /// Adds one scan taken with base_link at `base_in_map`; returns the scan's returns that the
  /// map does not explain, in base_link.
  std::vector<Eigen::Vector2d> AddScan(const LaserScanSample& scan, const Pose2& laser_in_base,
                                       const Pose2& base_in_map);
  /// Marks the remembered cells occupied on `grid` (a copy of the map), except those within
  /// `keep_clear` (a box in base_link: the robot's footprint and a margin — a return there is
  /// the robot's own or touching it, and marking it would put the planner's start in
  /// collision) of the robot at `robot_in_map`; returns how many cells it marked.
  int MarkOn(OccupancyGrid& grid, const Pose2& robot_in_map,
             const Eigen::AlignedBox2d& keep_clear) const;
  size_t size() const { return cells_.size(); }

 private:
  bool NearMappedObstacle(CellIndex cell) const;
  int64_t Key(CellIndex cell) const {
    return static_cast<int64_t>(cell.y) * map_->width() + cell.x;
  }

  std::shared_ptr<const OccupancyGrid> map_;
  UnmappedObstaclesParams params_;
  std::unordered_set<int64_t> cells_;
};

}  // namespace fleetnav::agent
