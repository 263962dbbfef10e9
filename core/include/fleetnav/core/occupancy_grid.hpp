#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"

namespace fleetnav {

enum class CellState { kFree, kOccupied, kUnknown };

struct CellIndex {
  int x = 0;
  int y = 0;
  bool operator==(const CellIndex&) const = default;
};

/// Largest grid accepted anywhere in fleetnav (cells). Larger grids are refused as
/// InvalidArgument so that a bad request cannot exhaust memory.
inline constexpr int64_t kMaxGridCells = 100'000'000;

/// A 2D occupancy grid in the ROS nav_msgs/OccupancyGrid convention: cell (0, 0) is the
/// lower-left cell, whose lower-left corner sits at `origin` (a pose in the map frame; its yaw
/// rotates the grid). Cells are stored row-major (index = y * width + x) as occupancy
/// probabilities in percent: 0 free, 100 occupied, -1 unknown. Values in between are mapped to a
/// state with the free/occupied thresholds of the map_server convention (≤ 25 free, ≥ 65
/// occupied). Invariants (checked by Create): width, height > 0, width·height ≤ kMaxGridCells,
/// resolution finite and > 0, origin finite, cells.size() == width·height, every cell in
/// [-1, 100]. A value type; thread-compatible.
class OccupancyGrid {
 public:
  static constexpr int8_t kFreeValue = 0;
  static constexpr int8_t kOccupiedValue = 100;
  static constexpr int8_t kUnknownValue = -1;

  /// Validates and builds a grid; errors are InvalidArgument naming the bad field.
  static absl::StatusOr<OccupancyGrid> Create(int width, int height, double resolution_m,
                                              const Pose2& origin, std::vector<int8_t> cells);
  /// A grid with every cell set to `fill`.
  static absl::StatusOr<OccupancyGrid> Filled(int width, int height, double resolution_m,
                                              const Pose2& origin, int8_t fill);

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return resolution_m_; }
  const Pose2& origin() const { return origin_; }
  const std::vector<int8_t>& cells() const { return cells_; }
  double width_m() const { return width_ * resolution_m_; }
  double height_m() const { return height_ * resolution_m_; }

  bool InBounds(CellIndex cell) const;
  /// Raw value of a cell; the cell must be in bounds.
  int8_t Value(CellIndex cell) const { return cells_[Index(cell)]; }
  void SetValue(CellIndex cell, int8_t value) { cells_[Index(cell)] = value; }
  CellState State(CellIndex cell) const;
  /// Occupied or unknown outside the grid? Outside counts as unknown.
  CellState StateAtWorld(const Eigen::Vector2d& point_in_map) const;

  /// The cell containing a map-frame point, or nullopt when outside the grid.
  std::optional<CellIndex> WorldToCell(const Eigen::Vector2d& point_in_map) const;
  /// The map-frame centre of a cell (the cell need not be in bounds).
  Eigen::Vector2d CellToWorld(CellIndex cell) const;
  /// True when the map-frame point lies inside the grid's extent.
  bool ContainsWorld(const Eigen::Vector2d& point_in_map) const;

  bool operator==(const OccupancyGrid& other) const;

 private:
  OccupancyGrid() = default;
  size_t Index(CellIndex cell) const { return static_cast<size_t>(cell.y) * width_ + cell.x; }

  int width_ = 0;
  int height_ = 0;
  double resolution_m_ = 0.0;
  Pose2 origin_;
  std::vector<int8_t> cells_;
};

}  // namespace fleetnav
