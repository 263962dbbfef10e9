#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/route.hpp"

namespace fleetnav::storage {

struct StoredRoute {
  Route route;
  uint32_t version = 0;
  int64_t created_unix_ms = 0;
};

/// Versioned routes by name (versions 1, 2, …). Thread-safe; a Put stores a whole route or
/// nothing.
class RouteRepository {
 public:
  virtual ~RouteRepository() = default;
  virtual absl::StatusOr<uint32_t> PutRoute(const Route& route, int64_t created_unix_ms) = 0;
  /// version 0 reads the latest; NotFound names the route (and version).
  virtual absl::StatusOr<StoredRoute> GetRoute(const std::string& name, uint32_t version) = 0;
  /// The latest version of every route, ordered by name; an empty map_id lists all maps.
  virtual absl::StatusOr<std::vector<StoredRoute>> ListRoutes(const std::string& map_id) = 0;
  /// How many routes (any version) are on `map_id`.
  virtual absl::StatusOr<int> CountRoutesOnMap(const std::string& map_id) = 0;
  /// Deletes every version of the route (a new one starts again at 1); NotFound names it.
  virtual absl::Status DeleteRoute(const std::string& name) = 0;
};

}  // namespace fleetnav::storage
