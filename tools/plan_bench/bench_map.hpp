#pragma once

#include <string>

#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"

namespace fleetnav::plan_bench {

/// The single-robot benchmark map of issue 4: 500 × 400 cells at 0.2 m (200 000 cells,
/// 100 × 80 m) with 80 random boxes of 0.6–3 m drawn with `seed`, and the two corner areas
/// (4, 4) and (78, 69) m kept free (the 74 m straight-line start and goal).
OccupancyGrid GeneratedMap(uint64_t seed);

/// A MovingAI map as an occupancy grid of `resolution_m` cells: passable cells free, the rest
/// occupied; the file's first row is the top (largest y) row of the grid.
absl::StatusOr<OccupancyGrid> MovingAiGrid(const std::string& path, double resolution_m);

}  // namespace fleetnav::plan_bench
