#pragma once

#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/storage/map_repository.hpp"
#include "fleetnav/storage/marker_set_repository.hpp"
#include "fleetnav/storage/route_repository.hpp"

namespace fleetnav::server {

struct SiteCacheParams {
  /// Approximate bytes of maps, marker sets and routes kept in memory; the least recently used
  /// leave first. An entry larger than the budget is served but not kept.
  int64_t budget_bytes = int64_t{128} << 20;
};

/// A read-through cache of a site's maps, marker sets and routes in front of their repositories,
/// so that the work of a dispatch, a telemetry message or a watch update does not grow with the
/// size of what is stored: a version is read and parsed once, then shared. Versions are
/// immutable, so an entry (id, version) never goes stale; the latest version of each id is
/// learned once and kept current by the writes that pass through here (every write of the
/// server does). Deleting a map forgets its versions, since a deleted id starts again at 1.
/// Implements the three repository interfaces, so it stands wherever they are used. Thread-safe;
/// reads from the repositories happen outside the cache's lock.
class SiteCache : public storage::MapRepository,
                  public storage::MarkerSetRepository,
                  public storage::RouteRepository {
 public:
  SiteCache(storage::MapRepository* maps, storage::MarkerSetRepository* markers,
            storage::RouteRepository* routes, SiteCacheParams params = {});

  /// version 0: the latest. NotFound as the repository says.
  absl::StatusOr<std::shared_ptr<const storage::StoredMap>> Map(const std::string& map_id,
                                                                uint32_t version);
  absl::StatusOr<std::shared_ptr<const storage::StoredMarkerSet>> MarkerSetVersion(
      const std::string& map_id, uint32_t version);
  absl::StatusOr<std::shared_ptr<const storage::StoredRoute>> RouteVersion(const std::string& name,
                                                                           uint32_t version);
  /// The latest version of the map; NotFound when there is none.
  absl::StatusOr<uint32_t> LatestMapVersion(const std::string& map_id);
  /// The latest version of the map's marker set; 0 when it has none.
  uint32_t LatestMarkerSetVersion(const std::string& map_id);

  // storage::MapRepository
  absl::StatusOr<MapInfo> PutMap(const std::string& map_id, const OccupancyGrid& grid,
                                 const std::string& description, int64_t created_unix_ms) override;
  absl::StatusOr<storage::StoredMap> GetMap(const std::string& map_id, uint32_t version) override;
  absl::StatusOr<std::vector<MapInfo>> ListMaps() override;
  absl::Status DeleteMap(const std::string& map_id) override;
  // storage::MarkerSetRepository
  absl::StatusOr<uint32_t> PutMarkerSet(const MarkerSet& markers, int64_t created_unix_ms) override;
  absl::StatusOr<storage::StoredMarkerSet> GetMarkerSet(const std::string& map_id,
                                                        uint32_t version) override;
  absl::Status DeleteMarkerSet(const std::string& map_id) override;
  // storage::RouteRepository
  absl::StatusOr<uint32_t> PutRoute(const Route& route, int64_t created_unix_ms) override;
  absl::StatusOr<storage::StoredRoute> GetRoute(const std::string& name, uint32_t version) override;
  absl::StatusOr<std::vector<storage::StoredRoute>> ListRoutes(const std::string& map_id) override;
  absl::StatusOr<int> CountRoutesOnMap(const std::string& map_id) override;
  absl::Status DeleteRoute(const std::string& name) override;

  /// Bytes held now (approximate), for tests and figures.
  int64_t held_bytes() const;

 private:
  enum class Kind { kMap, kMarkers, kRoute };
  using Key = std::tuple<Kind, std::string, uint32_t>;
  using Value = std::variant<std::shared_ptr<const storage::StoredMap>,
                             std::shared_ptr<const storage::StoredMarkerSet>,
                             std::shared_ptr<const storage::StoredRoute>>;
  struct Entry {
    Value value;
    int64_t bytes = 0;
    std::list<Key>::iterator recency;
  };

  /// The entry's value, marked most recently used; nullptr when absent.
  const Value* Find(const Key& key) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void Keep(const Key& key, Value value, int64_t bytes) ABSL_LOCKS_EXCLUDED(mutex_);
  void NoteLatest(Kind kind, const std::string& id, uint32_t version) ABSL_LOCKS_EXCLUDED(mutex_);
  /// The cached (kind, id, version), else what `read(version or 0)` returns, kept.
  template <typename Stored, typename ReadFn>
  absl::StatusOr<std::shared_ptr<const Stored>> ReadThrough(Kind kind, const std::string& id,
                                                            uint32_t version, ReadFn read)
      ABSL_LOCKS_EXCLUDED(mutex_);
  /// Drops every cached version of (kind, id) and what is known of its latest.
  void Forget(Kind kind, const std::string& id) ABSL_LOCKS_EXCLUDED(mutex_);
  /// Resolves version 0 to the latest known version, or 0 when not yet known.
  uint32_t Resolve(Kind kind, const std::string& id, uint32_t version) ABSL_LOCKS_EXCLUDED(mutex_);

  storage::MapRepository* maps_;
  storage::MarkerSetRepository* markers_;
  storage::RouteRepository* routes_;
  const SiteCacheParams params_;
  mutable absl::Mutex mutex_;
  std::map<Key, Entry> entries_ ABSL_GUARDED_BY(mutex_);
  std::list<Key> recency_ ABSL_GUARDED_BY(mutex_);  ///< front: most recently used
  int64_t held_bytes_ ABSL_GUARDED_BY(mutex_) = 0;
  std::map<std::pair<Kind, std::string>, uint32_t> latest_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav::server
