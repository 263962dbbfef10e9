#pragma once

#include <map>
#include <vector>

#include "absl/synchronization/mutex.h"
#include "fleetnav/storage/map_repository.hpp"

namespace fleetnav::storage {

/// MapRepository kept in memory, for unit tests of the layers above. Thread-safe.
class MemoryMapRepository final : public MapRepository {
 public:
  absl::StatusOr<MapInfo> PutMap(const std::string& map_id, const OccupancyGrid& grid,
                                 const std::string& description, int64_t created_unix_ms) override;
  absl::StatusOr<StoredMap> GetMap(const std::string& map_id, uint32_t version) override;
  absl::StatusOr<std::vector<MapInfo>> ListMaps() override;
  absl::Status DeleteMap(const std::string& map_id) override;

 private:
  absl::Mutex mutex_;
  std::map<std::string, std::vector<StoredMap>> maps_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav::storage
