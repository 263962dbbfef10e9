#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/storage/map_repository.hpp"

namespace fleetnav::server {

/// The use cases around maps: checks map ids, stamps creation time (Unix wall time), and stores
/// through a MapRepository. Thread-safe as its repository is.
class MapCatalog {
 public:
  explicit MapCatalog(storage::MapRepository* repository) : repository_(repository) {}

  absl::StatusOr<storage::MapInfo> Put(const std::string& map_id, const OccupancyGrid& grid,
                                       const std::string& description);
  absl::StatusOr<storage::StoredMap> Get(const std::string& map_id, uint32_t version);
  absl::StatusOr<std::vector<storage::MapInfo>> List();
  absl::Status Delete(const std::string& map_id);

  /// Map ids are 1-64 characters of [a-z0-9_-]; InvalidArgument names `map_id` otherwise.
  static absl::Status ValidateMapId(const std::string& map_id);

 private:
  storage::MapRepository* repository_;
};

}  // namespace fleetnav::server
