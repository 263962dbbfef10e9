#include "fleetnav/server/site/zone_catalog.hpp"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/server/site/map_catalog.hpp"

namespace fleetnav::server {

absl::StatusOr<uint32_t> ZoneCatalog::PutZones(const ZoneSet& zones) {
  RETURN_IF_ERROR(MapCatalog::ValidateMapId(zones.map_id));
  RETURN_IF_ERROR(limits_.CheckZones(zones));
  RETURN_IF_ERROR(zones.Validate());
  ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredMap> map, site_data_->Map(zones.map_id, 0));
  RETURN_IF_ERROR(CheckZonesOnMap(zones, map->grid));
  // The same content again is the version that holds it, not a new one.
  if (std::shared_ptr<const storage::StoredZoneSet> latest = Latest(zones.map_id);
      latest != nullptr && ZoneSetToYaml(latest->zones) == ZoneSetToYaml(zones)) {
    return latest->version;
  }
  const int64_t created_unix_ms = clock_->UnixMs();
  ASSIGN_OR_RETURN(const uint32_t version, zones_->PutZoneSet(zones, created_unix_ms));
  {
    absl::MutexLock lock(&mutex_);
    latest_[zones.map_id] = std::make_shared<const storage::StoredZoneSet>(
        storage::StoredZoneSet{zones, version, created_unix_ms});
  }
  if (on_change_) on_change_(zones.map_id);
  return version;
}

absl::StatusOr<storage::StoredZoneSet> ZoneCatalog::GetZones(const std::string& map_id,
                                                             uint32_t version) {
  RETURN_IF_ERROR(MapCatalog::ValidateMapId(map_id));
  return zones_->GetZoneSet(map_id, version);
}

absl::StatusOr<std::vector<storage::StoredZoneSet>> ZoneCatalog::ListZones() {
  return zones_->ListZoneSets();
}

absl::Status ZoneCatalog::DeleteZones(const std::string& map_id) {
  RETURN_IF_ERROR(MapCatalog::ValidateMapId(map_id));
  RETURN_IF_ERROR(zones_->DeleteZoneSet(map_id));
  {
    absl::MutexLock lock(&mutex_);
    latest_[map_id] = nullptr;
  }
  if (on_change_) on_change_(map_id);
  return absl::OkStatus();
}

std::shared_ptr<const storage::StoredZoneSet> ZoneCatalog::Latest(const std::string& map_id) {
  {
    absl::MutexLock lock(&mutex_);
    if (auto it = latest_.find(map_id); it != latest_.end()) return it->second;
  }
  absl::StatusOr<storage::StoredZoneSet> stored = zones_->GetZoneSet(map_id, 0);
  if (!stored.ok() && !absl::IsNotFound(stored.status())) return nullptr;
  std::shared_ptr<const storage::StoredZoneSet> latest =
      stored.ok() ? std::make_shared<const storage::StoredZoneSet>(*std::move(stored)) : nullptr;
  absl::MutexLock lock(&mutex_);
  // A write that passed meanwhile knows better than this read.
  return latest_.try_emplace(map_id, std::move(latest)).first->second;
}

absl::Status CheckOutsideNoGo(const ZoneSet* zones, const Eigen::Vector2d& point,
                              const std::string& field) {
  if (zones == nullptr) return absl::OkStatus();
  for (const Zone* zone : zones->Touching(ZoneKind::kNoGo, point, 0.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, absl::StrFormat(" (%.2f, %.2f)", point.x(), point.y()),
                     " lies in no-go zone '", zone->name, "' of map '", zones->map_id, "'"));
  }
  return absl::OkStatus();
}

}  // namespace fleetnav::server
