#include "fleetnav/server/site/map_catalog.hpp"

#include "absl/strings/str_cat.h"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::server {

absl::Status MapCatalog::ValidateMapId(const std::string& map_id) {
  bool ok = !map_id.empty() && map_id.size() <= 64;
  for (char c : map_id) {
    ok = ok && ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-');
  }
  if (!ok) {
    return absl::InvalidArgumentError(absl::StrCat(
        "map_id: must be 1-64 characters of [a-z0-9_-], got '", EchoInput(map_id), "'"));
  }
  return absl::OkStatus();
}

absl::StatusOr<MapInfo> MapCatalog::Put(const std::string& map_id, const OccupancyGrid& grid,
                                        const std::string& description) {
  RETURN_IF_ERROR(ValidateMapId(map_id));
  RETURN_IF_ERROR(limits_.CheckMap(grid));
  RETURN_IF_ERROR(limits_.CheckMapDescription(description));
  absl::StatusOr<MapInfo> info;
  // The same map and description again is the version that holds them, not a new one.
  if (absl::StatusOr<std::shared_ptr<const storage::StoredMap>> latest = site_data_->Map(map_id, 0);
      latest.ok() && (*latest)->info.description == description && (*latest)->grid == grid) {
    info = (*latest)->info;
  } else {
    info = site_data_->PutMap(map_id, grid, description, clock_->UnixMs());
  }
  if (info.ok() && on_change_) on_change_(map_id);
  return info;
}

absl::StatusOr<std::shared_ptr<const storage::StoredMap>> MapCatalog::Get(const std::string& map_id,
                                                                          uint32_t version) {
  RETURN_IF_ERROR(ValidateMapId(map_id));
  return site_data_->Map(map_id, version);
}

absl::StatusOr<uint32_t> MapCatalog::LatestVersion(const std::string& map_id) {
  RETURN_IF_ERROR(ValidateMapId(map_id));
  return site_data_->LatestMapVersion(map_id);
}

absl::StatusOr<std::vector<MapInfo>> MapCatalog::List() { return site_data_->ListMaps(); }

absl::Status MapCatalog::Delete(const std::string& map_id) {
  RETURN_IF_ERROR(ValidateMapId(map_id));
  return site_data_->DeleteMap(map_id);
}

}  // namespace fleetnav::server
