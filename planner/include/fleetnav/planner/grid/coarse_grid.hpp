#pragma once

#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/planner/grid/movingai.hpp"

namespace fleetnav::planner {

/// A map coarsened into square planning cells: a cell is free only if every map cell in it is
/// free. Cell (x, y) spans [x, x + 1) × [y, y + 1) cells of `cell_m` from `origin`, the map's
/// own origin. A value type.
struct CoarseGrid {
  MovingAiMap map;
  double cell_m = 1.0;
  Pose2 origin;

  /// The cell holding `pose`'s position (it may be off the grid or blocked).
  void CellOf(const Pose2& pose, int* x, int* y) const;
  /// The map-frame position of cell (x, y)'s centre.
  Eigen::Vector2d CenterOf(int x, int y) const;
};

/// `grid` in cells of at least `cell_m` (a whole number of map cells).
CoarseGrid Coarsen(const OccupancyGrid& grid, double cell_m);

}  // namespace fleetnav::planner
