#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/pose2.hpp"

namespace fleetnav::planner {

/// How unknown cells (and the outside of the grid) count.
enum class UnknownPolicy { kObstacle, kFree };

/// Parameters of Costmap.
struct CostmapParams {
  UnknownPolicy unknown = UnknownPolicy::kObstacle;
  int orientation_bins = 32;  ///< yaw discretisation of the footprint, ≥ 1
  double padding_m = 0.0;     ///< extra clearance around the footprint, ≥ 0

  absl::Status Validate() const;
};

/// A planning costmap built from an OccupancyGrid: the obstacle cells (occupied, and unknown
/// under UnknownPolicy::kObstacle), their Euclidean distance field (Felzenszwalb and
/// Huttenlocher, "Distance Transforms of Sampled Functions", Theory of Computing 2012: the
/// exact squared-distance transform by lower envelopes of parabolas, rows then columns), and a
/// footprint collision test for a polygon robot at any yaw: the footprint (padded) is
/// rasterised once per orientation bin into cell offsets that it overlaps (conservatively:
/// every cell whose centre lies within half a cell diagonal of the polygon), and a pose
/// collides when any offset lands on an obstacle — the Minkowski sum of the obstacles and the
/// footprint, evaluated lazily per (cell, bin) and cached. Distances below the inscribed radius
/// or above the circumscribed radius answer without rasterised checks. Cells are in the grid
/// frame; yaws are relative to the grid. Not thread-safe (the cache fills lazily).
class Costmap {
 public:
  static absl::StatusOr<Costmap> Build(const OccupancyGrid& grid,
                                       const std::vector<Eigen::Vector2d>& footprint_m,
                                       const CostmapParams& params);

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return resolution_m_; }
  bool InBounds(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
  /// Obstacle after the unknown policy; outside the grid follows the unknown policy.
  bool IsObstacle(int x, int y) const;
  /// Distance from the cell centre to the nearest obstacle cell centre, in metres.
  double DistanceToObstacle_m(int x, int y) const;
  /// True when the footprint at cell (x, y) with yaw (grid frame) touches no obstacle.
  bool FootprintFree(int x, int y, double yaw_rad);
  /// True when the footprint at cell (x, y) is free at some orientation bin: the cells a robot
  /// can be in at all, which a heuristic over cells may pass without overstating the way.
  bool AnyYawFree(int x, int y);
  /// The same for a continuous pose in the grid frame (metres from the grid's lower-left
  /// corner); the position is rounded to its cell.
  bool PoseFree(double x_m, double y_m, double yaw_rad);
  double inscribed_radius_m() const { return inscribed_m_; }
  double circumscribed_radius_m() const { return circumscribed_m_; }

 private:
  Costmap() = default;
  int Bin(double yaw_rad) const;

  int width_ = 0;
  int height_ = 0;
  double resolution_m_ = 0.0;
  bool unknown_is_obstacle_ = true;
  int bins_ = 1;
  double inscribed_m_ = 0.0;
  double circumscribed_m_ = 0.0;
  std::vector<uint8_t> obstacle_;
  std::vector<float> distance_m_;
  std::vector<std::vector<std::pair<int, int>>> offsets_;  // per bin
  std::vector<uint8_t> cache_;  // per (cell, bin): 0 unknown, 1 free, 2 collides
};

/// The exact 2D squared Euclidean distance transform (in cells²) of a binary grid:
/// Felzenszwalb–Huttenlocher. `obstacle` is row-major width × height; the result is the
/// squared distance of every cell to the nearest obstacle cell (a large value when none).
std::vector<double> SquaredDistanceTransform(const std::vector<uint8_t>& obstacle, int width,
                                             int height);

}  // namespace fleetnav::planner
