#pragma once

#include <string>
#include <vector>

namespace fleetnav::storage {

/// The schema migrations of fleetnavd's database, in order: entry i takes PRAGMA user_version
/// from i to i + 1. Append only; never edit a released migration.
const std::vector<std::string>& FleetSchemaMigrations();

}  // namespace fleetnav::storage
