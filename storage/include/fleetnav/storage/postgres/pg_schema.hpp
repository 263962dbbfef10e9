#pragma once

#include <string>
#include <vector>

namespace fleetnav::storage {

/// fleetnavd's schema in PostgreSQL's dialect: entry i takes `fleetnav_schema.version` from i
/// to i + 1, and version N holds the same tables and columns as the SQLite schema's version N
/// (FleetSchemaMigrations), so both engines run the same repositories. Append only.
const std::vector<std::string>& PostgresFleetSchemaMigrations();

}  // namespace fleetnav::storage
