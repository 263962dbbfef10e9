#include "fleetnav/planner/grid/swept_cells.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include "absl/container/flat_hash_set.h"
#include "fleetnav/core/segment_distance.hpp"

namespace fleetnav::planner {
namespace {

uint64_t Key(int64_t ix, int64_t iy) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(ix)) << 32) | static_cast<uint32_t>(iy);
}

int64_t KeyX(uint64_t key) { return static_cast<int32_t>(static_cast<uint32_t>(key >> 32)); }
int64_t KeyY(uint64_t key) {
  return static_cast<int32_t>(static_cast<uint32_t>(key & 0xffffffffU));
}

/// Distance from `p` to the polygon: 0 inside, else to the nearest edge.
double DistanceToPolygon(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& polygon) {
  bool inside = false;
  double best = std::numeric_limits<double>::infinity();
  const size_t n = polygon.size();
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const Eigen::Vector2d& a = polygon[j];
    const Eigen::Vector2d& b = polygon[i];
    if ((b.y() > p.y()) != (a.y() > p.y()) &&
        p.x() < (a.x() - b.x()) * (p.y() - b.y()) / (a.y() - b.y()) + b.x()) {
      inside = !inside;
    }
    best = std::min(best, PointSegmentDistance(p, a, b));
  }
  return inside ? 0.0 : best;
}

}  // namespace

CellSet CellSet::Sweep(const std::vector<Pose2>& poses,
                       const std::vector<Eigen::Vector2d>& footprint, double margin_m,
                       double cell_m) {
  CellSet out;
  const double reach_m = margin_m + cell_m * std::sqrt(0.5);
  std::vector<Eigen::Vector2d> placed(footprint.size());
  // Poses along an action are a few centimetres apart, so nearly every cell one pose touches
  // was already taken by the one before: each cell is tested and stored once.
  absl::flat_hash_set<uint64_t> taken;
  for (const Pose2& pose : poses) {
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d hi = -lo;
    for (size_t i = 0; i < footprint.size(); ++i) {
      placed[i] = pose.TransformPoint(footprint[i]);
      lo = lo.cwiseMin(placed[i]);
      hi = hi.cwiseMax(placed[i]);
    }
    const int64_t x0 = static_cast<int64_t>(std::floor((lo.x() - reach_m) / cell_m));
    const int64_t x1 = static_cast<int64_t>(std::floor((hi.x() + reach_m) / cell_m));
    const int64_t y0 = static_cast<int64_t>(std::floor((lo.y() - reach_m) / cell_m));
    const int64_t y1 = static_cast<int64_t>(std::floor((hi.y() + reach_m) / cell_m));
    for (int64_t ix = x0; ix <= x1; ++ix) {
      for (int64_t iy = y0; iy <= y1; ++iy) {
        const uint64_t key = Key(ix, iy);
        if (taken.contains(key)) continue;
        const Eigen::Vector2d centre((ix + 0.5) * cell_m, (iy + 0.5) * cell_m);
        if (DistanceToPolygon(centre, placed) > reach_m) continue;
        taken.insert(key);
        out.keys_.push_back(key);
        out.GrowBoundsBy(ix, iy);
      }
    }
  }
  std::sort(out.keys_.begin(), out.keys_.end());
  out.keys_.shrink_to_fit();  // a server keeps thousands of these
  return out;
}

void CellSet::GrowBoundsBy(int64_t ix, int64_t iy) {
  if (max_x_ < min_x_) {
    min_x_ = max_x_ = ix;
    min_y_ = max_y_ = iy;
  }
  min_x_ = std::min(min_x_, ix);
  max_x_ = std::max(max_x_, ix);
  min_y_ = std::min(min_y_, iy);
  max_y_ = std::max(max_y_, iy);
}

void CellSet::Add(const CellSet& other) {
  if (other.keys_.empty()) return;
  std::vector<uint64_t> merged;
  merged.reserve(keys_.size() + other.keys_.size());
  std::set_union(keys_.begin(), keys_.end(), other.keys_.begin(), other.keys_.end(),
                 std::back_inserter(merged));
  keys_ = std::move(merged);
  GrowBounds(other);
}

CellSet CellSet::OfCell(int64_t ix, int64_t iy) {
  CellSet out;
  out.keys_.push_back(Key(ix, iy));
  out.GrowBoundsBy(ix, iy);
  return out;
}

void CellSet::GrowBounds(const CellSet& other) {
  if (other.max_x_ < other.min_x_) return;
  if (max_x_ < min_x_) {
    min_x_ = other.min_x_;
    max_x_ = other.max_x_;
    min_y_ = other.min_y_;
    max_y_ = other.max_y_;
    return;
  }
  min_x_ = std::min(min_x_, other.min_x_);
  max_x_ = std::max(max_x_, other.max_x_);
  min_y_ = std::min(min_y_, other.min_y_);
  max_y_ = std::max(max_y_, other.max_y_);
}

bool CellSet::BoundsOverlap(const CellSet& other) const {
  return max_x_ >= min_x_ && other.max_x_ >= other.min_x_ && max_x_ >= other.min_x_ &&
         other.max_x_ >= min_x_ && max_y_ >= other.min_y_ && other.max_y_ >= min_y_;
}

bool CellSet::ContainsPoint(const Eigen::Vector2d& point_m, double cell_m) const {
  const int64_t ix = static_cast<int64_t>(std::floor(point_m.x() / cell_m));
  const int64_t iy = static_cast<int64_t>(std::floor(point_m.y() / cell_m));
  if (ix < min_x_ || ix > max_x_ || iy < min_y_ || iy > max_y_) return false;
  return std::binary_search(keys_.begin(), keys_.end(), Key(ix, iy));
}

bool CellSet::Intersects(const CellSet& other) const {
  if (keys_.empty() || other.keys_.empty() || !BoundsOverlap(other)) return false;
  auto a = keys_.begin();
  auto b = other.keys_.begin();
  while (a != keys_.end() && b != other.keys_.end()) {
    if (*a == *b) return true;
    if (*a < *b) {
      ++a;
    } else {
      ++b;
    }
  }
  return false;
}

std::vector<Eigen::Vector2d> CellSet::CellCentres(double cell_m) const {
  std::vector<Eigen::Vector2d> out;
  out.reserve(keys_.size());
  for (const uint64_t key : keys_) {
    out.emplace_back((KeyX(key) + 0.5) * cell_m, (KeyY(key) + 0.5) * cell_m);
  }
  return out;
}

}  // namespace fleetnav::planner
