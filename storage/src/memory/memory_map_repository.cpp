#include "fleetnav/storage/memory/memory_map_repository.hpp"

#include "absl/strings/str_cat.h"
#include "fleetnav/core/echo_input.hpp"

namespace fleetnav::storage {

absl::StatusOr<MapInfo> MemoryMapRepository::PutMap(const std::string& map_id,
                                                    const OccupancyGrid& grid,
                                                    const std::string& description,
                                                    int64_t created_unix_ms) {
  absl::MutexLock lock(&mutex_);
  std::vector<StoredMap>& versions = maps_[map_id];
  MapInfo info{map_id,
               static_cast<uint32_t>(versions.size() + 1),
               grid.width(),
               grid.height(),
               grid.resolution_m(),
               description,
               created_unix_ms};
  versions.push_back(StoredMap{info, grid});
  return info;
}

absl::StatusOr<StoredMap> MemoryMapRepository::GetMap(const std::string& map_id, uint32_t version) {
  absl::MutexLock lock(&mutex_);
  auto it = maps_.find(map_id);
  if (it == maps_.end() || it->second.empty()) {
    return absl::NotFoundError(absl::StrCat("map '", EchoInput(map_id), "' not found"));
  }
  if (version == 0) return it->second.back();
  if (version > it->second.size()) {
    return absl::NotFoundError(
        absl::StrCat("map '", EchoInput(map_id), "' has no version ", version));
  }
  return it->second[version - 1];
}

absl::StatusOr<std::vector<MapInfo>> MemoryMapRepository::ListMaps() {
  absl::MutexLock lock(&mutex_);
  std::vector<MapInfo> out;
  for (const auto& [id, versions] : maps_) {
    if (!versions.empty()) out.push_back(versions.back().info);
  }
  return out;
}

absl::Status MemoryMapRepository::DeleteMap(const std::string& map_id) {
  absl::MutexLock lock(&mutex_);
  if (maps_.erase(map_id) == 0) {
    return absl::NotFoundError(absl::StrCat("map '", EchoInput(map_id), "' not found"));
  }
  return absl::OkStatus();
}

}  // namespace fleetnav::storage
