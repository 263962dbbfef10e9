#include "bench_map.hpp"

#include <random>

#include "fleetnav/planner/grid/movingai.hpp"

namespace fleetnav::plan_bench {

OccupancyGrid GeneratedMap(uint64_t seed) {
  OccupancyGrid grid =
      OccupancyGrid::Filled(500, 400, 0.2, Pose2(), OccupancyGrid::kFreeValue).value();
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> x(20, 470), y(20, 370), size(3, 15);
  for (int k = 0; k < 80; ++k) {
    const int bx = x(rng), by = y(rng), sx = size(rng), sy = size(rng);
    for (int j = by; j < by + sy; ++j) {
      for (int i = bx; i < bx + sx; ++i) grid.SetValue({i, j}, OccupancyGrid::kOccupiedValue);
    }
  }
  for (int j = 0; j < 30; ++j) {
    for (int i = 0; i < 30; ++i) {
      grid.SetValue({i + 5, j + 5}, OccupancyGrid::kFreeValue);
      grid.SetValue({i + 375, j + 330}, OccupancyGrid::kFreeValue);
    }
  }
  return grid;
}

absl::StatusOr<OccupancyGrid> MovingAiGrid(const std::string& path, double resolution_m) {
  absl::StatusOr<planner::MovingAiMap> map = planner::LoadMovingAiMap(path);
  if (!map.ok()) return map.status();
  absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Filled(
      map->width, map->height, resolution_m, Pose2(), OccupancyGrid::kOccupiedValue);
  if (!grid.ok()) return grid.status();
  for (int row = 0; row < map->height; ++row) {
    for (int x = 0; x < map->width; ++x) {
      if (map->Passable(x, row)) {
        grid->SetValue({x, map->height - 1 - row}, OccupancyGrid::kFreeValue);
      }
    }
  }
  return grid;
}

}  // namespace fleetnav::plan_bench
