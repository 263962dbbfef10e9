#include "fleetnav/server/site/travel_distances.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include "fleetnav/planner/grid/coarse_grid.hpp"

namespace fleetnav::server {
namespace {

constexpr float kUnreached = std::numeric_limits<float>::infinity();

}  // namespace

TravelDistances::TravelDistances(SiteCache* site, TravelDistancesParams params)
    : site_(site), params_(params) {}

std::shared_ptr<const planner::CoarseGrid> TravelDistances::GridOf(const std::string& map_id,
                                                                   uint32_t version) {
  const auto key = std::make_pair(map_id, version);
  if (auto known = grids_.find(key); known != grids_.end()) return known->second;
  absl::StatusOr<std::shared_ptr<const storage::StoredMap>> stored = site_->Map(map_id, version);
  if (!stored.ok()) return nullptr;
  const OccupancyGrid& map = (*stored)->grid;
  // Square blocks of `factor` map cells, enough of them that the grid stays within max_cells.
  const double cells = static_cast<double>(map.width()) * map.height();
  int factor = std::max(1, static_cast<int>(std::ceil(params_.cell_m / map.resolution_m() - 1e-9)));
  while (cells / (static_cast<double>(factor) * factor) > static_cast<double>(params_.max_cells)) {
    ++factor;
  }
  auto grid = std::make_shared<const planner::CoarseGrid>(
      planner::Coarsen(map, factor * map.resolution_m()));
  if (grids_.size() >= 4) grids_.clear();  // maps change seldom; a handful is plenty
  grids_[key] = grid;
  return grid;
}

std::optional<int> TravelDistances::FreeCellNear(const planner::CoarseGrid& grid,
                                                 const Eigen::Vector2d& point) {
  int cx = 0;
  int cy = 0;
  grid.CellOf(Pose2(point.x(), point.y(), 0.0), &cx, &cy);
  std::optional<int> best;
  int best_ring = 3;
  for (int dy = -2; dy <= 2; ++dy) {
    for (int dx = -2; dx <= 2; ++dx) {
      const int ring = std::max(std::abs(dx), std::abs(dy));
      if (ring >= best_ring || !grid.map.Passable(cx + dx, cy + dy)) continue;
      best = (cy + dy) * grid.map.width + cx + dx;
      best_ring = ring;
    }
  }
  return best;
}

const std::vector<float>& TravelDistances::FieldTo(const std::string& map_id, uint32_t version,
                                                   const planner::CoarseGrid& grid, int cell) {
  const FieldKey key{map_id, version, cell};
  if (auto known = fields_.find(key); known != fields_.end()) {
    recent_.remove(key);
    recent_.push_front(key);
    return known->second;
  }
  // Dijkstra over 8 neighbours; a diagonal step needs both cells beside it free.
  const int width = grid.map.width;
  std::vector<float> field(grid.map.passable.size(), kUnreached);
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  field[static_cast<size_t>(cell)] = 0.0F;
  open.push({0.0F, cell});
  const float straight = static_cast<float>(grid.cell_m);
  const float diagonal = static_cast<float>(grid.cell_m * std::sqrt(2.0));
  const auto free_at = [&](int x, int y) { return grid.map.Passable(x, y); };
  while (!open.empty()) {
    const auto [d, at] = open.top();
    open.pop();
    if (d > field[static_cast<size_t>(at)]) continue;
    const int x = at % width;
    const int y = at / width;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx == 0 && dy == 0) || !free_at(x + dx, y + dy)) continue;
        if (dx != 0 && dy != 0 && !(free_at(x + dx, y) && free_at(x, y + dy))) continue;
        const float next = d + (dx != 0 && dy != 0 ? diagonal : straight);
        float& known = field[static_cast<size_t>((y + dy) * width + x + dx)];
        if (next < known) {
          known = next;
          open.push({next, (y + dy) * width + x + dx});
        }
      }
    }
  }
  while (fields_.size() >= params_.max_fields && !recent_.empty()) {
    fields_.erase(recent_.back());
    recent_.pop_back();
  }
  recent_.push_front(key);
  return fields_.emplace(key, std::move(field)).first->second;
}

std::optional<double> TravelDistances::Between(const std::string& map_id,
                                               const Eigen::Vector2d& from,
                                               const Eigen::Vector2d& to) {
  absl::StatusOr<uint32_t> version = site_->LatestMapVersion(map_id);
  if (!version.ok()) return std::nullopt;
  std::shared_ptr<const planner::CoarseGrid> grid = GridOf(map_id, *version);
  if (grid == nullptr || grid->map.passable.empty()) return std::nullopt;
  const std::optional<int> start = FreeCellNear(*grid, from);
  const std::optional<int> goal = FreeCellNear(*grid, to);
  if (!start || !goal) return std::nullopt;
  const float along = FieldTo(map_id, *version, *grid, *goal)[static_cast<size_t>(*start)];
  if (!std::isfinite(along)) return std::nullopt;
  return static_cast<double>(along);
}

}  // namespace fleetnav::server
