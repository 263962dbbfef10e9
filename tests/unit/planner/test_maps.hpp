#pragma once

#include <string>

#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/planner/grid/movingai.hpp"
#include "movingai_generators.hpp"

namespace fleetnav::planner::testing {

/// Parses an inline map given as rows of MovingAI characters; aborts the test on error.
inline MovingAiMap InlineMap(const std::string& rows_joined_by_newline, int width, int height) {
  std::string text = "type octile\nheight " + std::to_string(height) + "\nwidth " +
                     std::to_string(width) + "\nmap\n" + rows_joined_by_newline;
  return ParseMovingAiMap(text).value();
}

/// A seeded 32 × 32 map with 20 % obstacles, shaped like the benchmark's random-32-32-20.
inline MovingAiMap Random32Map20() { return fleetnav::testing::Random32Map20(); }
/// A seeded 32 × 32 map with 10 % obstacles, shaped like the benchmark's random-32-32-10.
inline MovingAiMap Random32Map10() { return fleetnav::testing::Random32Map10(); }

/// 24 m × 16 m at 0.1 m: a border, a wall at x = 12 m with a 4 m door (y 6–10 m), and two
/// boxes (5–7 × 10–12 m and 17–18.5 × 3–5 m).
inline OccupancyGrid DoorGrid() {
  OccupancyGrid grid =
      OccupancyGrid::Filled(240, 160, 0.1, Pose2(), OccupancyGrid::kFreeValue).value();
  for (int y = 0; y < 160; ++y) {
    for (int x = 0; x < 240; ++x) {
      const bool border = x < 2 || y < 2 || x >= 238 || y >= 158;
      const bool wall = x >= 118 && x < 122 && !(y >= 60 && y < 100);
      const bool box =
          (x >= 50 && x < 70 && y >= 100 && y < 120) || (x >= 170 && x < 185 && y >= 30 && y < 50);
      if (border || wall || box) grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
    }
  }
  return grid;
}

}  // namespace fleetnav::planner::testing
