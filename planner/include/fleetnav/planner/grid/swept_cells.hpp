#pragma once

#include <cstdint>
#include <vector>

#include "fleetnav/core/pose2.hpp"

namespace fleetnav::planner {

/// A region of the floor as the set of square cells (side cell_m, on a grid anchored at the
/// map origin's (0, 0)) that it touches; sorted keys, so two sets intersect in linear time.
/// Value type.
class CellSet {
 public:
  CellSet() = default;
  /// Every cell that a footprint (base_link polygon) placed at any of `poses` and grown by
  /// `margin_m` touches (cells whose centre lies within margin_m + half a cell diagonal).
  static CellSet Sweep(const std::vector<Pose2>& poses,
                       const std::vector<Eigen::Vector2d>& footprint, double margin_m,
                       double cell_m);

  /// The one cell (ix, iy): e.g. a token far off every map that two sets share to say that
  /// they exclude each other (planner::CapacityZones).
  static CellSet OfCell(int64_t ix, int64_t iy);

  bool Intersects(const CellSet& other) const;
  /// Adds `other`'s cells to this set (a union).
  void Add(const CellSet& other);
  /// Grows this set's bounds to cover `other`'s (the cells are not merged): a box to cull
  /// with before testing the sets it was built from.
  void GrowBounds(const CellSet& other);
  /// Whether the bounds of the two sets overlap (a necessary condition for Intersects).
  bool BoundsOverlap(const CellSet& other) const;
  /// Whether the cell holding `point_m` is in the set (`cell_m` as the set was swept with).
  bool ContainsPoint(const Eigen::Vector2d& point_m, double cell_m) const;
  /// The centres of the set's cells (`cell_m` as the set was swept with), in key order.
  std::vector<Eigen::Vector2d> CellCentres(double cell_m) const;
  bool empty() const { return keys_.empty(); }
  size_t size() const { return keys_.size(); }

 private:
  /// Adds a key to the bounds (not to keys_).
  void GrowBoundsBy(int64_t ix, int64_t iy);

  std::vector<uint64_t> keys_;
  /// Bounds of the cells (inclusive), so that far-apart sets are told apart without a merge.
  int64_t min_x_ = 0, max_x_ = -1, min_y_ = 0, max_y_ = -1;
};

}  // namespace fleetnav::planner
