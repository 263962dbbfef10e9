#include "bench_world.hpp"

#include <vector>

#include "fleetnav/localization/random.hpp"

namespace fleetnav::loc_bench {

absl::StatusOr<OccupancyGrid> BenchMap(uint64_t seed) {
  constexpr int kCells = 400;  // 20 m at 5 cm
  std::vector<int8_t> cells(kCells * kCells, 0);
  const auto fill = [&](int x0, int y0, int x1, int y1) {
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) cells[static_cast<size_t>(y) * kCells + x] = 100;
    }
  };
  fill(0, 0, kCells, 4);
  fill(0, kCells - 4, kCells, kCells);
  fill(0, 0, 4, kCells);
  fill(kCells - 4, 0, kCells, kCells);
  localization::Rng rng(seed);
  for (int i = 0; i < 25; ++i) {
    const int x = 20 + static_cast<int>(rng.UniformInt(kCells - 60));
    const int y = 20 + static_cast<int>(rng.UniformInt(kCells - 60));
    const int w = 4 + static_cast<int>(rng.UniformInt(30));
    const int h = 4 + static_cast<int>(rng.UniformInt(30));
    // Keep the centre (where the robot is) free.
    if (x < 230 && x + w > 170 && y < 230 && y + h > 170) continue;
    fill(x, y, x + w, y + h);
  }
  return OccupancyGrid::Create(kCells, kCells, 0.05, Pose2(-10.0, -10.0, 0.0), std::move(cells));
}

}  // namespace fleetnav::loc_bench
