#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fleetnav/storage/sqlite/sqlite_database.hpp"

namespace fleetnav::storage {

/// The schema migrations of fleetnavd's database, in order: entry i takes PRAGMA user_version
/// from i to i + 1. Append only; never edit a released migration.
const std::vector<std::string>& FleetSchemaMigrations();

/// `PRAGMA application_id` stamped into fleetnavd's database files: "FNAV".
inline constexpr uint32_t kFleetApplicationId = 0x464E4156;

/// How fleetnavd opens its database: only files stamped with kFleetApplicationId, new empty
/// files, or unstamped files of this schema (they hold a `maps` table) are taken.
SqliteOpenOptions FleetDatabaseOptions(Durability durability = Durability::kFull);

}  // namespace fleetnav::storage
