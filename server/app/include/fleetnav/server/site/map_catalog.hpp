#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/server/site/input_limits.hpp"
#include "fleetnav/server/site/site_cache.hpp"
#include "fleetnav/storage/map_repository.hpp"

namespace fleetnav::server {

/// The use cases around maps: checks map ids, stamps creation time (the injected clock's calendar),
/// and stores through a MapRepository. Thread-safe as its repository is.
class MapCatalog {
 public:
  MapCatalog(SiteCache* site_data, const Clock* clock, InputLimits limits = {})
      : site_data_(site_data), clock_(clock), limits_(limits) {}

  /// A new version, or the latest one when it holds the same cells and description.
  absl::StatusOr<MapInfo> Put(const std::string& map_id, const OccupancyGrid& grid,
                              const std::string& description);
  /// version 0: the latest. Shared with the cache: never copied.
  absl::StatusOr<std::shared_ptr<const storage::StoredMap>> Get(const std::string& map_id,
                                                                uint32_t version);
  /// NotFound when the map has no version.
  absl::StatusOr<uint32_t> LatestVersion(const std::string& map_id);
  absl::StatusOr<std::vector<MapInfo>> List();
  absl::Status Delete(const std::string& map_id);

  /// Told the map id after every successful Put (FleetApp: robots hear of the new version).
  /// Set before the catalog is shared.
  void SetChangeListener(std::function<void(const std::string& map_id)> listener) {
    on_change_ = std::move(listener);
  }

  /// Map ids are 1-64 characters of [a-z0-9_-]; InvalidArgument names `map_id` otherwise.
  static absl::Status ValidateMapId(const std::string& map_id);

 private:
  SiteCache* site_data_;
  const Clock* clock_;
  const InputLimits limits_;
  std::function<void(const std::string& map_id)> on_change_;
};

}  // namespace fleetnav::server
