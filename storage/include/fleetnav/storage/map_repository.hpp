#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/map_info.hpp"
#include "fleetnav/core/occupancy_grid.hpp"

namespace fleetnav::storage {

struct StoredMap {
  MapInfo info;
  OccupancyGrid grid;
};

/// Versioned occupancy-grid maps. Every Put creates version (latest + 1), starting at 1; a
/// deleted map id starts again at 1. Implementations are thread-safe and either store a whole
/// map or nothing.
class MapRepository {
 public:
  virtual ~MapRepository() = default;

  /// Stores a new version and returns its info.
  virtual absl::StatusOr<MapInfo> PutMap(const std::string& map_id, const OccupancyGrid& grid,
                                         const std::string& description,
                                         int64_t created_unix_ms) = 0;
  /// version 0 reads the latest. NotFound names the map id (and version).
  virtual absl::StatusOr<StoredMap> GetMap(const std::string& map_id, uint32_t version) = 0;
  /// The latest version of every map, ordered by id.
  virtual absl::StatusOr<std::vector<MapInfo>> ListMaps() = 0;
  /// Removes every version; NotFound when there is none.
  virtual absl::Status DeleteMap(const std::string& map_id) = 0;
};

}  // namespace fleetnav::storage
