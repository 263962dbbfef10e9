#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/zone.hpp"
#include "fleetnav/server/site/input_limits.hpp"
#include "fleetnav/server/site/site_cache.hpp"
#include "fleetnav/storage/zone_set_repository.hpp"

namespace fleetnav::server {

/// The use cases around a site's zones (issue 39): a zone set needs its map and must lie on it
/// (InvalidArgument naming `zones[i].polygon[j]`), every polygon simple and every figure in
/// range (ZoneSet::Validate); the same zones again are the version that holds them. Keeps the
/// latest set of each map parsed, so that the checks of every route put, job submission and
/// assignment read it without the store; every write of the server passes through here and
/// keeps it current. Thread-safe.
class ZoneCatalog {
 public:
  ZoneCatalog(storage::ZoneSetRepository* zones, SiteCache* site_data, const Clock* clock,
              InputLimits limits = {})
      : zones_(zones), site_data_(site_data), clock_(clock), limits_(limits) {}

  /// A new version, or the latest one when it holds the same zones.
  absl::StatusOr<uint32_t> PutZones(const ZoneSet& zones);
  /// version 0: the latest.
  absl::StatusOr<storage::StoredZoneSet> GetZones(const std::string& map_id, uint32_t version);
  /// The latest set of every map that has one, by map id.
  absl::StatusOr<std::vector<storage::StoredZoneSet>> ListZones();
  /// Every version of the map's zones; NotFound when it has none.
  absl::Status DeleteZones(const std::string& map_id);
  /// The map's latest zones, shared; nullptr when it has none (or the store cannot be read:
  /// a check then has no zones to hold against, as before zones existed).
  std::shared_ptr<const storage::StoredZoneSet> Latest(const std::string& map_id)
      ABSL_LOCKS_EXCLUDED(mutex_);
  /// Told the map id after every successful put or delete (FleetApp: robots hear of the new
  /// version). Set before the catalog is shared.
  void SetChangeListener(std::function<void(const std::string& map_id)> listener) {
    on_change_ = std::move(listener);
  }

 private:
  storage::ZoneSetRepository* zones_;
  SiteCache* site_data_;
  const Clock* clock_;  ///< stamps the upload time
  const InputLimits limits_;
  std::function<void(const std::string& map_id)> on_change_;
  absl::Mutex mutex_;
  /// Latest set per map id as read or written; nullptr: the map has none.
  std::map<std::string, std::shared_ptr<const storage::StoredZoneSet>> latest_
      ABSL_GUARDED_BY(mutex_);
};

/// InvalidArgument naming `field` and the zone when `point` lies in a no-go zone of `zones`
/// (nullptr: no zones).
absl::Status CheckOutsideNoGo(const ZoneSet* zones, const Eigen::Vector2d& point,
                              const std::string& field);

}  // namespace fleetnav::server
