#pragma once

#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/server/site/map_catalog.hpp"
#include "fleetnav/server/site/site_cache.hpp"
#include "fleetnav/server/site/site_catalog.hpp"
#include "fleetnav/storage/memory/memory_fleet_repositories.hpp"
#include "fleetnav/storage/memory/memory_map_repository.hpp"

namespace fleetnav::server::testing {

/// A site held in memory for tests of the layer above the store: the in-memory repositories, a
/// SiteCache and a SiteCatalog over them, and a 10 m × 10 m free map "hall" (0.1 m cells).
struct MemorySite {
  explicit MemorySite(const Clock* clock) : catalog(&cache, &jobs, clock) {
    const OccupancyGrid grid = OccupancyGrid::Filled(100, 100, 0.1, Pose2(), 0).value();
    hall_ok = MapCatalog(&cache, clock).Put("hall", grid, "").ok();
  }

  storage::MemoryMapRepository maps;
  storage::MemoryMarkerSetRepository markers;
  storage::MemoryRouteRepository routes;
  storage::MemoryRobotRepository robots;
  storage::MemoryJobRepository jobs;
  SiteCache cache{&maps, &markers, &routes};
  SiteCatalog catalog;
  bool hall_ok = false;  ///< whether map "hall" was stored
};

}  // namespace fleetnav::server::testing
