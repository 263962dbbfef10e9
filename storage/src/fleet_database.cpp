#include "fleetnav/storage/fleet_database.hpp"

#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/postgres/pg_schema.hpp"
#include "fleetnav/storage/sqlite/schema.hpp"

namespace fleetnav::storage {

absl::StatusOr<std::unique_ptr<SqlDatabase>> OpenFleetDatabase(const std::string& db,
                                                               const PgOpenOptions& postgres) {
  if (IsPostgresUri(db)) {
    ASSIGN_OR_RETURN(std::unique_ptr<PgDatabase> opened,
                     PgDatabase::Open(db, PostgresFleetSchemaMigrations(), postgres));
    return std::unique_ptr<SqlDatabase>(std::move(opened));
  }
  ASSIGN_OR_RETURN(std::unique_ptr<SqliteDatabase> opened,
                   SqliteDatabase::Open(db, FleetSchemaMigrations(), FleetDatabaseOptions()));
  return std::unique_ptr<SqlDatabase>(std::move(opened));
}

}  // namespace fleetnav::storage
