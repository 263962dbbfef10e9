#include "fleetnav/planner/grid/coarse_grid.hpp"

#include <algorithm>
#include <cmath>

namespace fleetnav::planner {

void CoarseGrid::CellOf(const Pose2& pose, int* x, int* y) const {
  const Eigen::Vector2d local = origin.Inverse().TransformPoint(pose.translation());
  *x = static_cast<int>(std::floor(local.x() / cell_m));
  *y = static_cast<int>(std::floor(local.y() / cell_m));
}

Eigen::Vector2d CoarseGrid::CenterOf(int x, int y) const {
  return origin.TransformPoint(Eigen::Vector2d((x + 0.5) * cell_m, (y + 0.5) * cell_m));
}

CoarseGrid Coarsen(const OccupancyGrid& grid, double cell_m) {
  CoarseGrid out;
  out.origin = grid.origin();
  const int factor = std::max(1, static_cast<int>(std::ceil(cell_m / grid.resolution_m() - 1e-9)));
  out.cell_m = factor * grid.resolution_m();
  out.map.width = grid.width() / factor;
  out.map.height = grid.height() / factor;
  out.map.passable.assign(static_cast<size_t>(out.map.width) * out.map.height, true);
  for (int cy = 0; cy < out.map.height; ++cy) {
    for (int cx = 0; cx < out.map.width; ++cx) {
      bool free = true;
      for (int y = cy * factor; free && y < (cy + 1) * factor; ++y) {
        for (int x = cx * factor; free && x < (cx + 1) * factor; ++x) {
          free = grid.State({x, y}) == CellState::kFree;
        }
      }
      out.map.passable[static_cast<size_t>(cy) * out.map.width + cx] = free;
    }
  }
  return out;
}

}  // namespace fleetnav::planner
