#pragma once

#include <memory>

#include "fleetnav/storage/map_repository.hpp"
#include "fleetnav/storage/sql/sql_database.hpp"

namespace fleetnav::storage {

/// MapRepository on an SqlDatabase: one row per map version with the cells as a BLOB. Each
/// call is one transaction. Thread-safe (shares the database's serialisation).
class SqlMapRepository final : public MapRepository {
 public:
  explicit SqlMapRepository(SqlDatabase* db) : db_(db) {}

  absl::StatusOr<MapInfo> PutMap(const std::string& map_id, const OccupancyGrid& grid,
                                 const std::string& description, int64_t created_unix_ms) override;
  absl::StatusOr<StoredMap> GetMap(const std::string& map_id, uint32_t version) override;
  absl::StatusOr<std::vector<MapInfo>> ListMaps() override;
  absl::Status DeleteMap(const std::string& map_id) override;

 private:
  SqlDatabase* db_;
};

}  // namespace fleetnav::storage
