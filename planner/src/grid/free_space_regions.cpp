#include "fleetnav/planner/grid/free_space_regions.hpp"

#include <algorithm>
#include <cmath>

namespace fleetnav::planner {

FreeSpaceRegions::FreeSpaceRegions(const Costmap& costmap)
    : width_(costmap.width()),
      height_(costmap.height()),
      resolution_m_(costmap.resolution_m()),
      region_(static_cast<size_t>(costmap.width()) * costmap.height(), kNone) {
  // Half a cell of slack: distances are between cell centres.
  const double fits_m = costmap.inscribed_radius_m() - 0.5 * resolution_m_;
  std::vector<uint8_t> fits(region_.size(), 0);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      fits[static_cast<size_t>(y) * width_ + x] = costmap.DistanceToObstacle_m(x, y) >= fits_m;
    }
  }
  std::vector<int> open;
  for (size_t seed = 0; seed < region_.size(); ++seed) {
    if (fits[seed] == 0 || region_[seed] != kNone) continue;
    const int label = region_count_++;
    region_[seed] = label;
    open.push_back(static_cast<int>(seed));
    while (!open.empty()) {
      const int index = open.back();
      open.pop_back();
      const int x = index % width_;
      const int y = index / width_;
      const int neighbours[4][2] = {{x + 1, y}, {x - 1, y}, {x, y + 1}, {x, y - 1}};
      for (const auto& [nx, ny] : neighbours) {
        if (nx < 0 || ny < 0 || nx >= width_ || ny >= height_) continue;
        const int n = ny * width_ + nx;
        if (fits[n] == 0 || region_[n] != kNone) continue;
        region_[n] = label;
        open.push_back(n);
      }
    }
  }
}

int FreeSpaceRegions::RegionAt(const Eigen::Vector2d& point_in_grid) const {
  const int x = static_cast<int>(std::floor(point_in_grid.x() / resolution_m_));
  const int y = static_cast<int>(std::floor(point_in_grid.y() / resolution_m_));
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return kNone;
  return region_[static_cast<size_t>(y) * width_ + x];
}

int FreeSpaceRegions::RegionNear(const Eigen::Vector2d& point_in_grid, double within_m) const {
  const int at = RegionAt(point_in_grid);
  if (at != kNone || within_m <= 0.0) return at;
  const int cx = static_cast<int>(std::floor(point_in_grid.x() / resolution_m_));
  const int cy = static_cast<int>(std::floor(point_in_grid.y() / resolution_m_));
  const int reach = static_cast<int>(std::ceil(within_m / resolution_m_));
  int best = kNone;
  double best_d2 = within_m * within_m;
  for (int y = std::max(cy - reach, 0); y <= std::min(cy + reach, height_ - 1); ++y) {
    for (int x = std::max(cx - reach, 0); x <= std::min(cx + reach, width_ - 1); ++x) {
      const int32_t region = region_[static_cast<size_t>(y) * width_ + x];
      if (region == kNone) continue;
      const Eigen::Vector2d centre((x + 0.5) * resolution_m_, (y + 0.5) * resolution_m_);
      const double d2 = (centre - point_in_grid).squaredNorm();
      if (d2 <= best_d2) {
        best_d2 = d2;
        best = region;
      }
    }
  }
  return best;
}

bool FreeSpaceRegions::Connected(const Eigen::Vector2d& a_in_grid, const Eigen::Vector2d& b_in_grid,
                                 double within_m) const {
  const int a = RegionNear(a_in_grid, within_m);
  return a != kNone && a == RegionNear(b_in_grid, within_m);
}

}  // namespace fleetnav::planner
