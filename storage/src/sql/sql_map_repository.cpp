#include "fleetnav/storage/sql/sql_map_repository.hpp"

#include "absl/strings/str_cat.h"
#include "delete_rows_internal.hpp"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::storage {
namespace {

constexpr char kSelectColumns[] =
    "SELECT map_id, version, width, height, resolution_m, description, created_unix_ms, "
    "origin_x_m, origin_y_m, origin_yaw_rad, cells FROM maps ";

MapInfo InfoFromRow(const SqlStatement& row) {
  MapInfo info;
  info.map_id = row.ColumnText(0);
  info.version = static_cast<uint32_t>(row.ColumnInt(1));
  info.width = static_cast<int>(row.ColumnInt(2));
  info.height = static_cast<int>(row.ColumnInt(3));
  info.resolution_m = row.ColumnDouble(4);
  info.description = row.ColumnText(5);
  info.created_unix_ms = row.ColumnInt(6);
  return info;
}

}  // namespace

absl::StatusOr<MapInfo> SqlMapRepository::PutMap(const std::string& map_id,
                                                 const OccupancyGrid& grid,
                                                 const std::string& description,
                                                 int64_t created_unix_ms) {
  MapInfo info{map_id,         0, grid.width(), grid.height(), grid.resolution_m(), description,
               created_unix_ms};
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    RETURN_IF_ERROR(db_->LockKey(absl::StrCat("maps:", map_id)));
    ASSIGN_OR_RETURN(SqlStatement latest,
                     db_->Prepare("SELECT COALESCE(MAX(version), 0) FROM maps WHERE map_id = ?"));
    latest.Bind(1, map_id);
    ASSIGN_OR_RETURN(bool has_row, latest.Step());
    info.version = static_cast<uint32_t>(has_row ? latest.ColumnInt(0) + 1 : 1);
    ASSIGN_OR_RETURN(SqlStatement insert,
                     db_->Prepare("INSERT INTO maps (map_id, version, width, height, "
                                  "resolution_m, origin_x_m, origin_y_m, origin_yaw_rad, cells, "
                                  "description, created_unix_ms) "
                                  "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"));
    const auto& cells = grid.cells();
    insert.Bind(1, map_id)
        .Bind(2, static_cast<int64_t>(info.version))
        .Bind(3, static_cast<int64_t>(grid.width()))
        .Bind(4, static_cast<int64_t>(grid.height()))
        .Bind(5, grid.resolution_m())
        .Bind(6, grid.origin().x_m())
        .Bind(7, grid.origin().y_m())
        .Bind(8, grid.origin().yaw_rad())
        .BindBlob(9, cells.data(), cells.size())
        .Bind(10, description)
        .Bind(11, created_unix_ms);
    return insert.Run();
  }));
  return info;
}

absl::StatusOr<StoredMap> SqlMapRepository::GetMap(const std::string& map_id, uint32_t version) {
  std::optional<StoredMap> found;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    const std::string where = version == 0 ? "WHERE map_id = ? ORDER BY version DESC LIMIT 1"
                                           : "WHERE map_id = ? AND version = ?";
    ASSIGN_OR_RETURN(SqlStatement query, db_->Prepare(absl::StrCat(kSelectColumns, where)));
    query.Bind(1, map_id);
    if (version != 0) query.Bind(2, static_cast<int64_t>(version));
    ASSIGN_OR_RETURN(bool has_row, query.Step());
    if (!has_row) return absl::OkStatus();
    MapInfo info = InfoFromRow(query);
    std::vector<uint8_t> blob = query.ColumnBlob(10);
    std::vector<int8_t> cells(blob.begin(), blob.end());
    ASSIGN_OR_RETURN(OccupancyGrid grid,
                     OccupancyGrid::Create(
                         info.width, info.height, info.resolution_m,
                         Pose2(query.ColumnDouble(7), query.ColumnDouble(8), query.ColumnDouble(9)),
                         std::move(cells)));
    found = StoredMap{std::move(info), std::move(grid)};
    return absl::OkStatus();
  }));
  if (!found) {
    return absl::NotFoundError(
        version == 0 ? absl::StrCat("map '", EchoInput(map_id), "' not found")
                     : absl::StrCat("map '", EchoInput(map_id), "' has no version ", version));
  }
  return *std::move(found);
}

absl::StatusOr<std::vector<MapInfo>> SqlMapRepository::ListMaps() {
  std::vector<MapInfo> out;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement query,
                     db_->Prepare("SELECT map_id, version, width, height, resolution_m, "
                                  "description, created_unix_ms FROM maps m WHERE version = "
                                  "(SELECT MAX(version) FROM maps WHERE map_id = m.map_id) "
                                  "ORDER BY map_id"));
    while (true) {
      ASSIGN_OR_RETURN(bool has_row, query.Step());
      if (!has_row) break;
      out.push_back(InfoFromRow(query));
    }
    return absl::OkStatus();
  }));
  return out;
}

absl::Status SqlMapRepository::DeleteMap(const std::string& map_id) {
  return DeleteRowsOrNotFound(db_, "DELETE FROM maps WHERE map_id = ?", map_id,
                              absl::StrCat("map '", EchoInput(map_id), "'"));
}

}  // namespace fleetnav::storage
