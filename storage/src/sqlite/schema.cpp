#include "fleetnav/storage/sqlite/schema.hpp"

namespace fleetnav::storage {

const std::vector<std::string>& FleetSchemaMigrations() {
  static const std::vector<std::string> kMigrations = {
      // 1: versioned maps.
      R"sql(
        CREATE TABLE maps (
          map_id TEXT NOT NULL,
          version INTEGER NOT NULL,
          width INTEGER NOT NULL,
          height INTEGER NOT NULL,
          resolution_m REAL NOT NULL,
          origin_x_m REAL NOT NULL,
          origin_y_m REAL NOT NULL,
          origin_yaw_rad REAL NOT NULL,
          cells BLOB NOT NULL,
          description TEXT NOT NULL DEFAULT '',
          created_unix_ms INTEGER NOT NULL,
          PRIMARY KEY (map_id, version)
        );
      )sql",
  };
  return kMigrations;
}

}  // namespace fleetnav::storage
