#include "fleetnav/server/site/site_cache.hpp"

#include <utility>

#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::server {
namespace {

constexpr int64_t kEntryOverheadBytes = 256;

int64_t BytesOf(const storage::StoredMap& map) {
  return kEntryOverheadBytes + static_cast<int64_t>(map.grid.cells().size());
}

int64_t BytesOf(const storage::StoredMarkerSet& set) {
  return kEntryOverheadBytes +
         static_cast<int64_t>(set.markers.markers.size() * sizeof(StripeMarker));
}

int64_t BytesOf(const storage::StoredRoute& stored) {
  int64_t bytes = kEntryOverheadBytes;
  for (const RouteAction& action : stored.route.actions) {
    bytes += sizeof(RouteAction);
    if (const auto* nav = std::get_if<FreeNavigationAction>(&action.params)) {
      bytes += static_cast<int64_t>(nav->waypoints_m.size() * sizeof(Eigen::Vector2d));
    }
  }
  return bytes;
}

uint32_t VersionOf(const storage::StoredMap& map) { return map.info.version; }
uint32_t VersionOf(const storage::StoredMarkerSet& set) { return set.version; }
uint32_t VersionOf(const storage::StoredRoute& route) { return route.version; }

}  // namespace

SiteCache::SiteCache(storage::MapRepository* maps, storage::MarkerSetRepository* markers,
                     storage::RouteRepository* routes, SiteCacheParams params)
    : maps_(maps), markers_(markers), routes_(routes), params_(params) {}

const SiteCache::Value* SiteCache::Find(const Key& key) {
  auto it = entries_.find(key);
  if (it == entries_.end()) return nullptr;
  recency_.splice(recency_.begin(), recency_, it->second.recency);
  return &it->second.value;
}

void SiteCache::Keep(const Key& key, Value value, int64_t bytes) {
  if (bytes > params_.budget_bytes) return;
  absl::MutexLock lock(&mutex_);
  if (entries_.count(key) > 0) return;  // another reader kept it meanwhile
  while (!recency_.empty() && held_bytes_ + bytes > params_.budget_bytes) {
    auto oldest = entries_.find(recency_.back());
    held_bytes_ -= oldest->second.bytes;
    entries_.erase(oldest);
    recency_.pop_back();
  }
  recency_.push_front(key);
  entries_.emplace(key, Entry{std::move(value), bytes, recency_.begin()});
  held_bytes_ += bytes;
}

void SiteCache::NoteLatest(Kind kind, const std::string& id, uint32_t version) {
  absl::MutexLock lock(&mutex_);
  uint32_t& latest = latest_[{kind, id}];
  if (version > latest) latest = version;
}

uint32_t SiteCache::Resolve(Kind kind, const std::string& id, uint32_t version) {
  if (version != 0) return version;
  absl::MutexLock lock(&mutex_);
  auto it = latest_.find({kind, id});
  return it == latest_.end() ? 0 : it->second;
}

template <typename Stored, typename ReadFn>
absl::StatusOr<std::shared_ptr<const Stored>> SiteCache::ReadThrough(Kind kind,
                                                                     const std::string& id,
                                                                     uint32_t version,
                                                                     ReadFn read) {
  const uint32_t wanted = Resolve(kind, id, version);
  if (wanted != 0) {
    absl::MutexLock lock(&mutex_);
    if (const Value* found = Find({kind, id, wanted})) {
      return std::get<std::shared_ptr<const Stored>>(*found);
    }
  }
  absl::StatusOr<Stored> stored = read(wanted);
  if (!stored.ok()) return stored.status();
  auto shared = std::make_shared<const Stored>(*std::move(stored));
  if (version == 0) NoteLatest(kind, id, VersionOf(*shared));
  Keep({kind, id, VersionOf(*shared)}, shared, BytesOf(*shared));
  return shared;
}

absl::StatusOr<std::shared_ptr<const storage::StoredMap>> SiteCache::Map(const std::string& map_id,
                                                                         uint32_t version) {
  return ReadThrough<storage::StoredMap>(Kind::kMap, map_id, version,
                                         [&](uint32_t v) { return maps_->GetMap(map_id, v); });
}

absl::StatusOr<std::shared_ptr<const storage::StoredMarkerSet>> SiteCache::MarkerSetVersion(
    const std::string& map_id, uint32_t version) {
  return ReadThrough<storage::StoredMarkerSet>(Kind::kMarkers, map_id, version, [&](uint32_t v) {
    return markers_->GetMarkerSet(map_id, v);
  });
}

absl::StatusOr<std::shared_ptr<const storage::StoredRoute>> SiteCache::RouteVersion(
    const std::string& name, uint32_t version) {
  return ReadThrough<storage::StoredRoute>(Kind::kRoute, name, version,
                                           [&](uint32_t v) { return routes_->GetRoute(name, v); });
}

absl::StatusOr<uint32_t> SiteCache::LatestMapVersion(const std::string& map_id) {
  if (const uint32_t known = Resolve(Kind::kMap, map_id, 0); known != 0) return known;
  ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredMap> map, Map(map_id, 0));
  return map->info.version;
}

uint32_t SiteCache::LatestMarkerSetVersion(const std::string& map_id) {
  {
    absl::MutexLock lock(&mutex_);
    auto it = latest_.find({Kind::kMarkers, map_id});
    if (it != latest_.end()) return it->second;  // 0: known to have none
  }
  absl::StatusOr<std::shared_ptr<const storage::StoredMarkerSet>> set = MarkerSetVersion(map_id, 0);
  if (set.ok()) return (*set)->version;
  if (absl::IsNotFound(set.status())) NoteLatest(Kind::kMarkers, map_id, 0);
  return 0;
}

absl::StatusOr<MapInfo> SiteCache::PutMap(const std::string& map_id, const OccupancyGrid& grid,
                                          const std::string& description, int64_t created_unix_ms) {
  ASSIGN_OR_RETURN(MapInfo info, maps_->PutMap(map_id, grid, description, created_unix_ms));
  NoteLatest(Kind::kMap, map_id, info.version);
  return info;
}

absl::StatusOr<storage::StoredMap> SiteCache::GetMap(const std::string& map_id, uint32_t version) {
  ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredMap> map, Map(map_id, version));
  return *map;
}

absl::StatusOr<std::vector<MapInfo>> SiteCache::ListMaps() { return maps_->ListMaps(); }

void SiteCache::Forget(Kind kind, const std::string& id) {
  absl::MutexLock lock(&mutex_);
  latest_.erase({kind, id});
  for (auto it = entries_.lower_bound({kind, id, 0});
       it != entries_.end() && std::get<0>(it->first) == kind && std::get<1>(it->first) == id;) {
    held_bytes_ -= it->second.bytes;
    recency_.erase(it->second.recency);
    it = entries_.erase(it);
  }
}

absl::Status SiteCache::DeleteMap(const std::string& map_id) {
  absl::Status deleted = maps_->DeleteMap(map_id);
  // Forgotten even when the delete failed part way: the next read asks the store again.
  Forget(Kind::kMap, map_id);
  return deleted;
}

absl::Status SiteCache::DeleteMarkerSet(const std::string& map_id) {
  absl::Status deleted = markers_->DeleteMarkerSet(map_id);
  Forget(Kind::kMarkers, map_id);
  return deleted;
}

absl::Status SiteCache::DeleteRoute(const std::string& name) {
  absl::Status deleted = routes_->DeleteRoute(name);
  Forget(Kind::kRoute, name);
  return deleted;
}

absl::StatusOr<uint32_t> SiteCache::PutMarkerSet(const MarkerSet& markers,
                                                 int64_t created_unix_ms) {
  ASSIGN_OR_RETURN(uint32_t version, markers_->PutMarkerSet(markers, created_unix_ms));
  NoteLatest(Kind::kMarkers, markers.map_id, version);
  return version;
}

absl::StatusOr<storage::StoredMarkerSet> SiteCache::GetMarkerSet(const std::string& map_id,
                                                                 uint32_t version) {
  ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredMarkerSet> set,
                   MarkerSetVersion(map_id, version));
  return *set;
}

absl::StatusOr<uint32_t> SiteCache::PutRoute(const Route& route, int64_t created_unix_ms) {
  ASSIGN_OR_RETURN(uint32_t version, routes_->PutRoute(route, created_unix_ms));
  NoteLatest(Kind::kRoute, route.name, version);
  return version;
}

absl::StatusOr<storage::StoredRoute> SiteCache::GetRoute(const std::string& name,
                                                         uint32_t version) {
  ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredRoute> route, RouteVersion(name, version));
  return *route;
}

absl::StatusOr<std::vector<storage::StoredRoute>> SiteCache::ListRoutes(const std::string& map_id) {
  return routes_->ListRoutes(map_id);
}

absl::StatusOr<int> SiteCache::CountRoutesOnMap(const std::string& map_id) {
  return routes_->CountRoutesOnMap(map_id);
}

int64_t SiteCache::held_bytes() const {
  absl::MutexLock lock(&mutex_);
  return held_bytes_;
}

}  // namespace fleetnav::server
