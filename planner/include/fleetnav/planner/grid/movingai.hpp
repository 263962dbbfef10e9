#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"

namespace fleetnav::planner {

/// A grid map in the MovingAI benchmark format (Sturtevant, "Benchmarks for Grid-Based
/// Pathfinding", IEEE TCIAIG 2012): `type`, `height`, `width`, `map`, then `height` rows of
/// `width` characters. Cell (x, y) is column x of row y, row 0 being the first row of the file.
/// '.', 'G' and 'S' are passable; '@', 'O', 'T' and 'W' are not. A value type.
struct MovingAiMap {
  int width = 0;
  int height = 0;
  std::vector<bool> passable;  ///< row-major, index = y * width + x

  bool Passable(int x, int y) const {
    return x >= 0 && y >= 0 && x < width && y < height &&
           passable[static_cast<size_t>(y) * width + x];
  }
};

/// One line of a MovingAI `.scen` file: a start and a goal cell on a named map.
struct ScenarioEntry {
  int bucket = 0;
  std::string map_name;
  int map_width = 0;
  int map_height = 0;
  int start_x = 0;
  int start_y = 0;
  int goal_x = 0;
  int goal_y = 0;
  double optimal_length = 0.0;
};

/// Parses the text of a `.map` file. Errors are InvalidArgument naming the line (1-based).
absl::StatusOr<MovingAiMap> ParseMovingAiMap(std::string_view text);
/// Reads and parses a `.map` file; NotFound when it cannot be opened.
absl::StatusOr<MovingAiMap> LoadMovingAiMap(const std::string& path);

/// Parses the text of a `.scen` file ("version 1" header, then tab-separated entries). Errors
/// are InvalidArgument naming the line (1-based).
absl::StatusOr<std::vector<ScenarioEntry>> ParseMovingAiScenario(std::string_view text);
/// Reads and parses a `.scen` file; NotFound when it cannot be opened.
absl::StatusOr<std::vector<ScenarioEntry>> LoadMovingAiScenario(const std::string& path);

}  // namespace fleetnav::planner
