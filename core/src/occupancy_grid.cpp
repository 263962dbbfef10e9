#include "fleetnav/core/occupancy_grid.hpp"

#include <cmath>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace fleetnav {
namespace {

// map_server thresholds in percent: at or below kFreeMaxValue is free, at or above
// kOccupiedMinValue is occupied, anything between (or negative) is unknown.
constexpr int kFreeMaxValue = 25;
constexpr int kOccupiedMinValue = 65;

absl::Status ValidateGrid(int width, int height, double resolution_m, const Pose2& origin,
                          const std::vector<int8_t>& cells) {
  if (width <= 0) return absl::InvalidArgumentError(absl::StrCat("width must be > 0, got ", width));
  if (height <= 0) {
    return absl::InvalidArgumentError(absl::StrCat("height must be > 0, got ", height));
  }
  const int64_t cell_count = static_cast<int64_t>(width) * height;
  if (cell_count > kMaxGridCells) {
    return absl::InvalidArgumentError(
        absl::StrCat("width*height = ", cell_count, " cells exceeds the limit of ", kMaxGridCells));
  }
  if (!std::isfinite(resolution_m) || resolution_m <= 0.0) {
    return absl::InvalidArgumentError(
        absl::StrFormat("resolution_m must be finite and > 0, got %g", resolution_m));
  }
  if (!origin.IsFinite()) {
    return absl::InvalidArgumentError(
        absl::StrCat("origin must be finite, got ", origin.DebugString()));
  }
  if (static_cast<int64_t>(cells.size()) != cell_count) {
    return absl::InvalidArgumentError(absl::StrCat("cells.size() = ", cells.size(),
                                                   " does not match width*height = ", cell_count));
  }
  for (size_t i = 0; i < cells.size(); ++i) {
    if (cells[i] < OccupancyGrid::kUnknownValue || cells[i] > OccupancyGrid::kOccupiedValue) {
      return absl::InvalidArgumentError(
          absl::StrCat("cells[", i, "] = ", static_cast<int>(cells[i]), " is outside [-1, 100]"));
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<OccupancyGrid> OccupancyGrid::Create(int width, int height, double resolution_m,
                                                    const Pose2& origin,
                                                    std::vector<int8_t> cells) {
  if (absl::Status status = ValidateGrid(width, height, resolution_m, origin, cells);
      !status.ok()) {
    return status;
  }
  OccupancyGrid grid;
  grid.width_ = width;
  grid.height_ = height;
  grid.resolution_m_ = resolution_m;
  grid.origin_ = origin;
  grid.cells_ = std::move(cells);
  return grid;
}

absl::StatusOr<OccupancyGrid> OccupancyGrid::Filled(int width, int height, double resolution_m,
                                                    const Pose2& origin, int8_t fill) {
  if (width <= 0 || height <= 0 || static_cast<int64_t>(width) * height > kMaxGridCells) {
    // Let Create report the exact problem without allocating a huge vector first.
    return Create(width, height, resolution_m, origin, {});
  }
  return Create(width, height, resolution_m, origin,
                std::vector<int8_t>(static_cast<size_t>(width) * height, fill));
}

bool OccupancyGrid::InBounds(CellIndex cell) const {
  return cell.x >= 0 && cell.y >= 0 && cell.x < width_ && cell.y < height_;
}

CellState OccupancyGrid::State(CellIndex cell) const {
  const int value = Value(cell);
  if (value < 0) return CellState::kUnknown;
  if (value <= kFreeMaxValue) return CellState::kFree;
  if (value >= kOccupiedMinValue) return CellState::kOccupied;
  return CellState::kUnknown;
}

CellState OccupancyGrid::StateAtWorld(const Eigen::Vector2d& point_in_map) const {
  const std::optional<CellIndex> cell = WorldToCell(point_in_map);
  return cell.has_value() ? State(*cell) : CellState::kUnknown;
}

std::optional<CellIndex> OccupancyGrid::WorldToCell(const Eigen::Vector2d& point_in_map) const {
  // Rotate and shift the point into the grid frame, whose origin is the lower-left corner.
  const Eigen::Vector2d point_in_grid = origin_.Inverse().TransformPoint(point_in_map);
  const double fx = std::floor(point_in_grid.x() / resolution_m_);
  const double fy = std::floor(point_in_grid.y() / resolution_m_);
  // Compare as doubles first: NaN and huge values must not reach the int conversion.
  if (!(fx >= 0.0 && fy >= 0.0 && fx < width_ && fy < height_)) return std::nullopt;
  return CellIndex{static_cast<int>(fx), static_cast<int>(fy)};
}

Eigen::Vector2d OccupancyGrid::CellToWorld(CellIndex cell) const {
  const Eigen::Vector2d centre_in_grid((cell.x + 0.5) * resolution_m_,
                                       (cell.y + 0.5) * resolution_m_);
  return origin_.TransformPoint(centre_in_grid);
}

bool OccupancyGrid::ContainsWorld(const Eigen::Vector2d& point_in_map) const {
  return WorldToCell(point_in_map).has_value();
}

bool OccupancyGrid::operator==(const OccupancyGrid& other) const {
  return width_ == other.width_ && height_ == other.height_ &&
         resolution_m_ == other.resolution_m_ && origin_.x_m() == other.origin_.x_m() &&
         origin_.y_m() == other.origin_.y_m() && origin_.yaw_rad() == other.origin_.yaw_rad() &&
         cells_ == other.cells_;
}

}  // namespace fleetnav
