#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/server/site/input_limits.hpp"
#include "fleetnav/server/site/site_cache.hpp"
#include "fleetnav/server/site/zone_catalog.hpp"
#include "fleetnav/storage/job_repository.hpp"
#include "fleetnav/storage/map_repository.hpp"
#include "fleetnav/storage/marker_set_repository.hpp"
#include "fleetnav/storage/route_repository.hpp"

namespace fleetnav::server {

/// The use cases around a site's marker sets and routes, checked against its maps: a marker
/// set needs its map; a route needs its map, may only name markers of the map's latest marker
/// set, and its free-navigation waypoints and goals must lie on free cells inside the map
/// (InvalidArgument naming `actions[i]`), outside every no-go zone of the map when it has
/// zones (UseZones). Also answers whether a map is still in use, so that
/// deleting it can be refused. Thread-safe as its repositories are.
class SiteCatalog {
 public:
  SiteCatalog(SiteCache* site_data, storage::JobRepository* jobs, const Clock* clock,
              InputLimits limits = {})
      : site_data_(site_data), jobs_(jobs), clock_(clock), limits_(limits) {}

  /// A new version, or the latest one when it holds the same markers.
  absl::StatusOr<uint32_t> PutMarkerSet(const MarkerSet& markers);
  /// Told the map id after every successful PutMarkerSet (FleetApp: robots hear of the new
  /// version). Set before the catalog is shared.
  void SetMarkerChangeListener(std::function<void(const std::string& map_id)> listener) {
    on_marker_change_ = std::move(listener);
  }
  /// The zones routes are checked against (no-go zones hold no waypoint or goal). Set before
  /// the catalog is shared; without it routes are checked against the map alone.
  void UseZones(ZoneCatalog* zones) { zones_ = zones; }
  /// The latest zone-set version of the map; 0 when it has none (or no zones are used).
  uint32_t LatestZoneSetVersion(const std::string& map_id);
  /// InvalidArgument naming `field` and the zone when `point` lies in a no-go zone of the map's
  /// latest zones.
  absl::Status CheckOutsideNoGo(const std::string& map_id, const Eigen::Vector2d& point,
                                const std::string& field);
  /// InvalidArgument naming `actions[i]` and the zone when a free-navigation waypoint or goal
  /// of the route lies in a no-go zone of its map's latest zones (which may have come after
  /// the route was stored).
  absl::Status CheckRouteOutsideNoGo(const Route& route);
  /// version 0: the latest. Shared with the cache: never copied.
  absl::StatusOr<std::shared_ptr<const storage::StoredMarkerSet>> GetMarkerSet(
      const std::string& map_id, uint32_t version);
  /// The latest marker-set version of the map; 0 when it has none.
  uint32_t LatestMarkerSetVersion(const std::string& map_id);
  /// A new version, or the latest one when it holds the same route.
  absl::StatusOr<uint32_t> PutRoute(const Route& route);
  absl::StatusOr<std::shared_ptr<const storage::StoredRoute>> GetRoute(const std::string& name,
                                                                       uint32_t version);
  absl::StatusOr<std::vector<storage::StoredRoute>> ListRoutes(const std::string& map_id);
  /// Deletes every version of a map's marker set: NotFound when it has none,
  /// FailedPrecondition naming a route of the map that ends at one of its markers or follows
  /// one of its stripes, or an unfinished job on the map.
  absl::Status DeleteMarkerSet(const std::string& map_id);
  /// Deletes every version of a route: NotFound for an unknown one, FailedPrecondition naming
  /// an unfinished job that runs it.
  absl::Status DeleteRoute(const std::string& name);
  /// FailedPrecondition naming what still uses the map (routes, unfinished jobs), else deletes.
  absl::Status DeleteMap(const std::string& map_id);

  /// Route names are 1-64 characters of [A-Za-z0-9_.-].
  static absl::Status ValidateRouteName(const std::string& name);

 private:
  /// The id of an unfinished job on the map, if there is one.
  absl::StatusOr<std::optional<std::string>> UnfinishedJobOnMap(const std::string& map_id);
  absl::Status CheckRouteAgainstSite(const Route& route);

  SiteCache* site_data_;
  storage::JobRepository* jobs_;
  const Clock* clock_;  ///< stamps the upload time of marker sets and routes
  const InputLimits limits_;
  std::function<void(const std::string& map_id)> on_marker_change_;
  ZoneCatalog* zones_ = nullptr;
};

}  // namespace fleetnav::server
