#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "fleetnav/server/site/site_cache.hpp"

namespace fleetnav::planner {
struct CoarseGrid;
}  // namespace fleetnav::planner

namespace fleetnav::server {

struct TravelDistancesParams {
  /// Planning cells of at least this size (a whole number of map cells); larger on maps whose
  /// cells would otherwise exceed max_cells.
  double cell_m = 0.5;
  int64_t max_cells = int64_t{1} << 20;
  /// Distance fields kept (one per destination cell and map version); the least recently used
  /// leave first.
  size_t max_fields = 32;
};

/// How far a robot has to drive on a site's map to reach a place: the length of the shortest
/// 8-connected path through free cells of the map coarsened to planning cells (a coarse cell is
/// free only when every map cell in it is), computed by Dijkstra from the destination once and
/// kept, so that the dispatcher ranks every idle robot for a job with one search. Not
/// thread-safe (the dispatcher calls it under its own lock).
class TravelDistances {
 public:
  explicit TravelDistances(SiteCache* site, TravelDistancesParams params = {});

  /// The path length from `from` to `to` on the latest version of `map_id`; nullopt when the
  /// map cannot be read, either end is off it, or no free path joins them. An end in a blocked
  /// cell (a robot beside a wall) starts from the nearest free cell within two cells.
  std::optional<double> Between(const std::string& map_id, const Eigen::Vector2d& from,
                                const Eigen::Vector2d& to);

 private:
  using FieldKey = std::tuple<std::string, uint32_t, int>;  ///< map, version, destination cell

  std::shared_ptr<const planner::CoarseGrid> GridOf(const std::string& map_id, uint32_t version);
  const std::vector<float>& FieldTo(const std::string& map_id, uint32_t version,
                                    const planner::CoarseGrid& grid, int cell);
  /// The free cell at or near `point` (nullopt: none within two cells, or off the grid).
  static std::optional<int> FreeCellNear(const planner::CoarseGrid& grid,
                                         const Eigen::Vector2d& point);

  SiteCache* site_;
  TravelDistancesParams params_;
  std::map<std::pair<std::string, uint32_t>, std::shared_ptr<const planner::CoarseGrid>> grids_;
  std::list<FieldKey> recent_;  ///< most recent first
  std::map<FieldKey, std::vector<float>> fields_;
};

}  // namespace fleetnav::server
