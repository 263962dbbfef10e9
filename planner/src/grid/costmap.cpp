#include "fleetnav/planner/grid/costmap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/distance_transform.hpp"
#include "fleetnav/core/segment_distance.hpp"

namespace fleetnav::planner {
namespace {

constexpr double kInf = 1e20;

bool InsidePolygon(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& poly) {
  bool inside = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

double DistanceToPolygon(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& poly) {
  if (InsidePolygon(p, poly)) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    best = std::min(best, PointSegmentDistance(p, poly[j], poly[i]));
  }
  return best;
}

}  // namespace

std::vector<double> SquaredDistanceTransform(const std::vector<uint8_t>& obstacle, int width,
                                             int height) {
  std::vector<double> grid(obstacle.size());
  for (size_t i = 0; i < obstacle.size(); ++i) grid[i] = obstacle[i] ? 0.0 : kInf;
  const int n = std::max(width, height);
  std::vector<double> f(n), d(n), z(n + 1);
  std::vector<int> v(n);
  for (int x = 0; x < width; ++x) {
    for (int y = 0; y < height; ++y) f[y] = grid[static_cast<size_t>(y) * width + x];
    SquaredDistanceTransform1d(f.data(), height, d.data(), v.data(), z.data());
    for (int y = 0; y < height; ++y) grid[static_cast<size_t>(y) * width + x] = d[y];
  }
  for (int y = 0; y < height; ++y) {
    double* row = &grid[static_cast<size_t>(y) * width];
    std::copy(row, row + width, f.begin());
    SquaredDistanceTransform1d(f.data(), width, d.data(), v.data(), z.data());
    std::copy(d.begin(), d.begin() + width, row);
  }
  return grid;
}

absl::Status CostmapParams::Validate() const {
  if (orientation_bins < 1 || orientation_bins > 360) {
    return absl::InvalidArgumentError("orientation_bins: must be in [1, 360]");
  }
  if (!(padding_m >= 0.0) || !std::isfinite(padding_m)) {
    return absl::InvalidArgumentError("padding_m: must be finite and >= 0");
  }
  return absl::OkStatus();
}

absl::StatusOr<Costmap> Costmap::Build(const OccupancyGrid& grid,
                                       const std::vector<Eigen::Vector2d>& footprint_m,
                                       const CostmapParams& params) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (footprint_m.size() < 3) {
    return absl::InvalidArgumentError(
        absl::StrCat("footprint_m: needs at least 3 points, got ", footprint_m.size()));
  }
  for (size_t i = 0; i < footprint_m.size(); ++i) {
    if (!footprint_m[i].allFinite()) {
      return absl::InvalidArgumentError(absl::StrCat("footprint_m[", i, "]: not finite"));
    }
  }
  Costmap map;
  map.width_ = grid.width();
  map.height_ = grid.height();
  map.resolution_m_ = grid.resolution_m();
  map.unknown_is_obstacle_ = params.unknown == UnknownPolicy::kObstacle;
  map.bins_ = params.orientation_bins;
  map.obstacle_.resize(static_cast<size_t>(map.width_) * map.height_);
  for (int y = 0; y < map.height_; ++y) {
    for (int x = 0; x < map.width_; ++x) {
      const CellState s = grid.State({x, y});
      map.obstacle_[static_cast<size_t>(y) * map.width_ + x] =
          s == CellState::kOccupied || (s == CellState::kUnknown && map.unknown_is_obstacle_);
    }
  }
  const std::vector<double> d2 = SquaredDistanceTransform(map.obstacle_, map.width_, map.height_);
  map.distance_m_.resize(d2.size());
  for (size_t i = 0; i < d2.size(); ++i) {
    map.distance_m_[i] = static_cast<float>(std::sqrt(d2[i]) * map.resolution_m_);
  }
  // Radii of the padded footprint about base_link.
  const Eigen::Vector2d origin(0, 0);
  map.circumscribed_m_ = 0.0;
  for (const auto& p : footprint_m) map.circumscribed_m_ = std::max(map.circumscribed_m_, p.norm());
  map.circumscribed_m_ += params.padding_m;
  map.inscribed_m_ = 0.0;
  if (InsidePolygon(origin, footprint_m)) {
    map.inscribed_m_ = std::numeric_limits<double>::infinity();
    for (size_t i = 0, j = footprint_m.size() - 1; i < footprint_m.size(); j = i++) {
      map.inscribed_m_ =
          std::min(map.inscribed_m_, PointSegmentDistance(origin, footprint_m[j], footprint_m[i]));
    }
    map.inscribed_m_ += params.padding_m;
  }
  // Rasterise the footprint per orientation bin.
  const double res = map.resolution_m_;
  const double half_diag = res * std::sqrt(0.5);
  const int reach = static_cast<int>(std::ceil((map.circumscribed_m_ + half_diag) / res)) + 1;
  map.offsets_.resize(map.bins_);
  for (int b = 0; b < map.bins_; ++b) {
    const double yaw = 2.0 * kPi * b / map.bins_;
    const double c = std::cos(yaw), s = std::sin(yaw);
    std::vector<Eigen::Vector2d> rotated;
    for (const auto& p : footprint_m)
      rotated.emplace_back(c * p.x() - s * p.y(), s * p.x() + c * p.y());
    for (int dy = -reach; dy <= reach; ++dy) {
      for (int dx = -reach; dx <= reach; ++dx) {
        const Eigen::Vector2d centre(dx * res, dy * res);
        if (DistanceToPolygon(centre, rotated) <= half_diag + params.padding_m) {
          map.offsets_[b].push_back({dx, dy});
        }
      }
    }
  }
  map.cache_.assign(map.obstacle_.size() * map.bins_, 0);
  return map;
}

bool Costmap::IsObstacle(int x, int y) const {
  if (!InBounds(x, y)) return unknown_is_obstacle_;
  return obstacle_[static_cast<size_t>(y) * width_ + x] != 0;
}

double Costmap::DistanceToObstacle_m(int x, int y) const {
  if (!InBounds(x, y)) return 0.0;
  return distance_m_[static_cast<size_t>(y) * width_ + x];
}

int Costmap::Bin(double yaw_rad) const {
  const double turns = yaw_rad / (2.0 * kPi);
  const double frac = turns - std::floor(turns);
  return static_cast<int>(std::lround(frac * bins_)) % bins_;
}

bool Costmap::FootprintFree(int x, int y, double yaw_rad) {
  if (!InBounds(x, y)) return false;
  const size_t cell = static_cast<size_t>(y) * width_ + x;
  const double clearance = distance_m_[cell];
  // Conservative shortcuts: a cell-centre distance above the circumscribed radius plus a cell
  // diagonal is free at every yaw; an obstacle strictly inside the inscribed circle collides.
  if (clearance > circumscribed_m_ + 1.5 * resolution_m_ &&
      (!unknown_is_obstacle_ || (x - (circumscribed_m_ / resolution_m_) - 2 >= 0 &&
                                 y - (circumscribed_m_ / resolution_m_) - 2 >= 0 &&
                                 x + (circumscribed_m_ / resolution_m_) + 2 < width_ &&
                                 y + (circumscribed_m_ / resolution_m_) + 2 < height_))) {
    return true;
  }
  if (clearance < inscribed_m_ - resolution_m_) return false;
  const int b = Bin(yaw_rad);
  uint8_t& cached = cache_[cell * bins_ + b];
  if (cached == 0) {
    bool free = true;
    for (const auto& [dx, dy] : offsets_[b]) {
      if (IsObstacle(x + dx, y + dy)) {
        free = false;
        break;
      }
    }
    cached = free ? 1 : 2;
  }
  return cached == 1;
}

bool Costmap::AnyYawFree(int x, int y) {
  for (int b = 0; b < bins_; ++b) {
    if (FootprintFree(x, y, 2.0 * kPi * b / bins_)) return true;
  }
  return false;
}

bool Costmap::PoseFree(double x_m, double y_m, double yaw_rad) {
  return FootprintFree(static_cast<int>(std::floor(x_m / resolution_m_)),
                       static_cast<int>(std::floor(y_m / resolution_m_)), yaw_rad);
}

}  // namespace fleetnav::planner
