#pragma once

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "fleetnav/storage/postgres/pg_database.hpp"
#include "fleetnav/storage/sql/sql_database.hpp"

namespace fleetnav::storage {

/// Opens fleetnavd's store from its `--db` value: a postgresql:// (or postgres://) URI opens
/// that PostgreSQL database with the PostgreSQL schema (PgDatabase, `postgres` options);
/// anything else is the path of an SQLite file, created if missing, opened with the SQLite
/// schema and fleetnavd's ownership checks. Both are migrated to the same schema version.
absl::StatusOr<std::unique_ptr<SqlDatabase>> OpenFleetDatabase(const std::string& db,
                                                               const PgOpenOptions& postgres = {});

}  // namespace fleetnav::storage
