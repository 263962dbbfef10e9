#pragma once

// Seeded generators of MovingAI-format maps and scenarios with the shape of the benchmark
// families (Stern et al., "Multi-Agent Pathfinding: Definitions, Variants, and Benchmarks",
// SoCS 2019): random maps with a given obstacle share, warehouses with shelf rows, and large
// open maps divided into rooms. Tests use them so that a clone of the repository with nothing
// beside it passes; the real benchmark files stay an optional input of the benchmark programs.

#include <algorithm>
#include <cstdint>
#include <deque>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "fleetnav/planner/grid/movingai.hpp"

namespace fleetnav::testing {

/// Text of a MovingAI `.map` file: rows of '.' (free) and '@' (blocked), row 0 first.
inline std::string MovingAiMapText(const std::vector<std::string>& rows) {
  std::ostringstream out;
  out << "type octile\nheight " << rows.size() << "\nwidth "
      << (rows.empty() ? 0 : rows.front().size()) << "\nmap\n";
  for (const std::string& row : rows) out << row << "\n";
  return out.str();
}

/// 4-connected breadth-first distances (in cells) from `start` over the free cells of `rows`;
/// -1 where unreachable.
inline std::vector<int> BfsDistances(const std::vector<std::string>& rows, int start) {
  const int height = static_cast<int>(rows.size());
  const int width = height == 0 ? 0 : static_cast<int>(rows.front().size());
  std::vector<int> dist(static_cast<size_t>(width * height), -1);
  std::deque<int> open{start};
  dist[start] = 0;
  while (!open.empty()) {
    const int cell = open.front();
    open.pop_front();
    const int x = cell % width, y = cell / width;
    const int nx[4] = {x + 1, x - 1, x, x};
    const int ny[4] = {y, y, y + 1, y - 1};
    for (int k = 0; k < 4; ++k) {
      if (nx[k] < 0 || ny[k] < 0 || nx[k] >= width || ny[k] >= height) continue;
      const int n = ny[k] * width + nx[k];
      if (rows[ny[k]][nx[k]] != '.' || dist[n] >= 0) continue;
      dist[n] = dist[cell] + 1;
      open.push_back(n);
    }
  }
  return dist;
}

/// Blocks every free cell outside the largest 4-connected free region, so that any two free
/// cells of the result are connected (the benchmark scenarios only use that region too).
inline void KeepLargestRegion(std::vector<std::string>& rows) {
  const int height = static_cast<int>(rows.size());
  const int width = height == 0 ? 0 : static_cast<int>(rows.front().size());
  std::vector<bool> seen(static_cast<size_t>(width * height), false);
  std::vector<int> best_dist;
  size_t best_size = 0;
  for (int start = 0; start < width * height; ++start) {
    if (rows[start / width][start % width] != '.' || seen[start]) continue;
    std::vector<int> dist = BfsDistances(rows, start);
    size_t size = 0;
    for (int cell = 0; cell < width * height; ++cell) {
      if (dist[cell] < 0) continue;
      seen[cell] = true;
      ++size;
    }
    if (size > best_size) best_size = size, best_dist = std::move(dist);
  }
  for (int cell = 0; cell < width * height; ++cell) {
    if (best_dist.empty() || best_dist[cell] < 0) rows[cell / width][cell % width] = '@';
  }
}

/// A random map like the benchmark's random-W-H-P: each cell blocked with probability
/// `obstacle_percent` / 100, then only the largest connected region kept free.
inline std::vector<std::string> RandomMapRows(int width, int height, int obstacle_percent,
                                              uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> percent(0, 99);
  std::vector<std::string> rows(static_cast<size_t>(height), std::string(width, '.'));
  for (std::string& row : rows) {
    for (char& c : row) c = percent(rng) < obstacle_percent ? '@' : '.';
  }
  KeepLargestRegion(rows);
  return rows;
}

/// A warehouse like warehouse-10-20-10-2-1: `shelf_rows` × `shelf_columns` shelves of
/// `shelf_length` × 1 cells, aisles of `aisle_width` cells between and around them.
inline std::vector<std::string> WarehouseMapRows(int shelf_rows, int shelf_columns,
                                                 int shelf_length, int aisle_width) {
  const int width = shelf_columns * (shelf_length + aisle_width) + aisle_width;
  const int height = shelf_rows * (1 + aisle_width) + aisle_width;
  std::vector<std::string> rows(static_cast<size_t>(height), std::string(width, '.'));
  for (int r = 0; r < shelf_rows; ++r) {
    const int y = aisle_width + r * (1 + aisle_width);
    for (int c = 0; c < shelf_columns; ++c) {
      const int x0 = aisle_width + c * (shelf_length + aisle_width);
      for (int x = x0; x < x0 + shelf_length; ++x) rows[y][x] = '@';
    }
  }
  return rows;
}

/// A large open map divided into rooms like room-W-H-R: walls every `room_size` + 1 cells in
/// both directions, each wall segment between two rooms with one random door of one cell.
inline std::vector<std::string> RoomsMapRows(int rooms_x, int rooms_y, int room_size,
                                             uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> door(0, room_size - 1);
  const int width = rooms_x * (room_size + 1) - 1;
  const int height = rooms_y * (room_size + 1) - 1;
  std::vector<std::string> rows(static_cast<size_t>(height), std::string(width, '.'));
  for (int ry = 0; ry < rooms_y; ++ry) {
    for (int rx = 0; rx < rooms_x; ++rx) {
      const int x0 = rx * (room_size + 1), y0 = ry * (room_size + 1);
      if (rx + 1 < rooms_x) {  // wall to the east with one door
        const int wall_x = x0 + room_size, open_y = y0 + door(rng);
        for (int y = y0; y < y0 + room_size; ++y) rows[y][wall_x] = y == open_y ? '.' : '@';
        if (ry + 1 < rooms_y) rows[y0 + room_size][wall_x] = '@';
      }
      if (ry + 1 < rooms_y) {  // wall to the south with one door
        const int wall_y = y0 + room_size, open_x = x0 + door(rng);
        for (int x = x0; x < x0 + room_size; ++x) rows[wall_y][x] = x == open_x ? '.' : '@';
      }
    }
  }
  return rows;
}

/// Parses generated rows through the real MovingAI parser.
inline planner::MovingAiMap ToMovingAiMap(const std::vector<std::string>& rows) {
  return planner::ParseMovingAiMap(MovingAiMapText(rows)).value();
}

/// The 32 × 32 map with 20 % obstacles (seed 1) that stands in for random-32-32-20.
inline planner::MovingAiMap Random32Map20() { return ToMovingAiMap(RandomMapRows(32, 32, 20, 1)); }
/// The 32 × 32 map with 10 % obstacles (seed 1) that stands in for random-32-32-10.
inline planner::MovingAiMap Random32Map10() { return ToMovingAiMap(RandomMapRows(32, 32, 10, 1)); }

/// Text of a `.scen` file with `count` entries whose starts are distinct and whose goals are
/// distinct, drawn (seeded) from the free cells of `rows`. The optimal length column holds the
/// 4-connected BFS distance, as MovingAI's does for its own metric.
inline std::string ScenarioText(const std::vector<std::string>& rows, const std::string& map_name,
                                int count, uint64_t seed) {
  const int height = static_cast<int>(rows.size());
  const int width = static_cast<int>(rows.front().size());
  std::vector<int> free_cells;
  for (int cell = 0; cell < width * height; ++cell) {
    if (rows[cell / width][cell % width] == '.') free_cells.push_back(cell);
  }
  std::mt19937_64 rng(seed);
  std::vector<int> starts = free_cells, goals = free_cells;
  std::shuffle(starts.begin(), starts.end(), rng);
  std::shuffle(goals.begin(), goals.end(), rng);
  std::ostringstream out;
  out << "version 1\n";
  for (int i = 0; i < count && i < static_cast<int>(free_cells.size()); ++i) {
    const std::vector<int> dist = BfsDistances(rows, starts[i]);
    out << i / 10 << "\t" << map_name << "\t" << width << "\t" << height << "\t"
        << starts[i] % width << "\t" << starts[i] / width << "\t" << goals[i] % width << "\t"
        << goals[i] / width << "\t" << dist[goals[i]] << "\n";
  }
  return out.str();
}

/// Writes `text` to `path`, replacing it; returns false when the file cannot be written.
inline bool WriteTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  return static_cast<bool>(out);
}

}  // namespace fleetnav::testing
