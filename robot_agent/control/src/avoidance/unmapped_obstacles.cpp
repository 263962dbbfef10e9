#include "fleetnav/robot_agent/control/avoidance/unmapped_obstacles.hpp"

#include <cmath>
#include <optional>

#include "fleetnav/robot_agent/scan_features.hpp"

namespace fleetnav::agent {

absl::Status UnmappedObstaclesParams::Validate() const {
  if (!(std::isfinite(explained_by_map_m) && explained_by_map_m >= 0.0 &&
        std::isfinite(clearing_range_m) && clearing_range_m >= 0.0)) {
    return absl::InvalidArgumentError(
        "unmapped obstacles: explained_by_map_m >= 0 and clearing_range_m >= 0 required");
  }
  return absl::OkStatus();
}

UnmappedObstacles::UnmappedObstacles(std::shared_ptr<const OccupancyGrid> map,
                                     UnmappedObstaclesParams params)
    : map_(std::move(map)), params_(params) {}

bool UnmappedObstacles::NearMappedObstacle(CellIndex cell) const {
  const int reach = static_cast<int>(std::ceil(params_.explained_by_map_m / map_->resolution_m()));
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const CellIndex c{cell.x + dx, cell.y + dy};
      if (map_->InBounds(c) && map_->State(c) == CellState::kOccupied) return true;
    }
  }
  return false;
}

std::vector<Eigen::Vector2d> UnmappedObstacles::AddScan(const LaserScanSample& scan,
                                                        const Pose2& laser_in_base,
                                                        const Pose2& base_in_map) {
  // Clear along every beam, short of its return.
  const Pose2 laser_in_map = base_in_map * laser_in_base;
  const double step_m = 0.5 * map_->resolution_m();
  for (size_t i = 0; i < scan.ranges_m.size() && !cells_.empty(); ++i) {
    const double range = scan.ranges_m[i];
    if (std::isnan(range)) continue;  // masked: no reading, it clears nothing
    const bool hit = std::isfinite(range) && range < scan.range_max_m;
    const double clear_to_m =
        std::min(hit ? range - map_->resolution_m() : scan.range_max_m, params_.clearing_range_m);
    const double angle = laser_in_map.yaw_rad() + scan.angle_min_rad +
                         static_cast<double>(i) * scan.angle_increment_rad;
    const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
    for (double t = 0.0; t < clear_to_m; t += step_m) {
      if (const std::optional<CellIndex> cell =
              map_->WorldToCell(laser_in_map.translation() + t * direction)) {
        cells_.erase(Key(*cell));
      }
    }
  }
  // Mark the returns the map does not explain.
  std::vector<Eigen::Vector2d> unexplained;
  for (const Eigen::Vector2d& p : ScanPoints(scan, laser_in_base)) {
    const std::optional<CellIndex> cell = map_->WorldToCell(base_in_map.TransformPoint(p));
    if (cell && NearMappedObstacle(*cell)) continue;
    unexplained.push_back(p);
    if (cell) cells_.insert(Key(*cell));
  }
  return unexplained;
}

int UnmappedObstacles::MarkOn(OccupancyGrid& grid, const Pose2& robot_in_map,
                              const Eigen::AlignedBox2d& keep_clear) const {
  const Pose2 robot_from_map = robot_in_map.Inverse();
  int marked = 0;
  for (const int64_t key : cells_) {
    const CellIndex cell{static_cast<int>(key % map_->width()),
                         static_cast<int>(key / map_->width())};
    if (!grid.InBounds(cell)) continue;
    if (keep_clear.contains(robot_from_map.TransformPoint(grid.CellToWorld(cell)))) continue;
    if (grid.State(cell) != CellState::kOccupied) {
      grid.SetValue(cell, OccupancyGrid::kOccupiedValue);
      ++marked;
    }
  }
  return marked;
}

}  // namespace fleetnav::agent
