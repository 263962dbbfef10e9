#include "absl/strings/str_cat.h"
#include "delete_rows_internal.hpp"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/sql/sql_fleet_repositories.hpp"
#include "versioned_rows_internal.hpp"

namespace fleetnav::storage {
namespace {

// A zone_sets row (version, yaml, created_unix_ms in columns 0-2) as a stored set of `map_id`.
absl::StatusOr<StoredZoneSet> ZoneSetFromRow(SqlStatement& row, const std::string& map_id) {
  ASSIGN_OR_RETURN(ZoneSet zones, ParseZoneSetYaml(row.ColumnText(1)));
  zones.map_id = map_id;
  return StoredZoneSet{std::move(zones), static_cast<uint32_t>(row.ColumnInt(0)), row.ColumnInt(2)};
}

}  // namespace

absl::StatusOr<uint32_t> SqlZoneSetRepository::PutZoneSet(const ZoneSet& zones,
                                                          int64_t created_unix_ms) {
  uint32_t version = 0;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(version, NextVersion(db_, "zone_sets", "map_id", zones.map_id));
    ASSIGN_OR_RETURN(SqlStatement insert,
                     db_->Prepare("INSERT INTO zone_sets (map_id, version, yaml, "
                                  "created_unix_ms) VALUES (?, ?, ?, ?)"));
    insert.Bind(1, zones.map_id)
        .Bind(2, static_cast<int64_t>(version))
        .Bind(3, ZoneSetToYaml(zones))
        .Bind(4, created_unix_ms);
    return insert.Run();
  }));
  return version;
}

absl::StatusOr<StoredZoneSet> SqlZoneSetRepository::GetZoneSet(const std::string& map_id,
                                                               uint32_t version) {
  std::optional<StoredZoneSet> found;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(
        SqlStatement query,
        db_->Prepare(version == 0 ? "SELECT version, yaml, created_unix_ms FROM zone_sets WHERE "
                                    "map_id = ? ORDER BY version DESC LIMIT 1"
                                  : "SELECT version, yaml, created_unix_ms FROM zone_sets WHERE "
                                    "map_id = ? AND version = ?"));
    query.Bind(1, map_id);
    if (version != 0) query.Bind(2, static_cast<int64_t>(version));
    ASSIGN_OR_RETURN(bool has_row, query.Step());
    if (!has_row) return absl::OkStatus();
    ASSIGN_OR_RETURN(found, ZoneSetFromRow(query, map_id));
    return absl::OkStatus();
  }));
  if (!found) {
    return absl::NotFoundError(absl::StrCat("zones of map '", EchoInput(map_id), "'",
                                            version == 0 ? " not found" : "",
                                            VersionText(version)));
  }
  return *std::move(found);
}

absl::StatusOr<std::vector<StoredZoneSet>> SqlZoneSetRepository::ListZoneSets() {
  std::vector<StoredZoneSet> out;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement query,
                     db_->Prepare("SELECT version, yaml, created_unix_ms, map_id FROM zone_sets z "
                                  "WHERE version = (SELECT MAX(version) FROM zone_sets WHERE "
                                  "map_id = z.map_id) ORDER BY map_id"));
    while (true) {
      ASSIGN_OR_RETURN(bool has_row, query.Step());
      if (!has_row) break;
      ASSIGN_OR_RETURN(StoredZoneSet stored, ZoneSetFromRow(query, query.ColumnText(3)));
      out.push_back(std::move(stored));
    }
    return absl::OkStatus();
  }));
  return out;
}

absl::Status SqlZoneSetRepository::DeleteZoneSet(const std::string& map_id) {
  return DeleteRowsOrNotFound(db_, "DELETE FROM zone_sets WHERE map_id = ?", map_id,
                              absl::StrCat("zones of map '", EchoInput(map_id), "'"));
}

}  // namespace fleetnav::storage
