#include "absl/strings/str_cat.h"
#include "delete_rows_internal.hpp"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/sql/sql_fleet_repositories.hpp"
#include "versioned_rows_internal.hpp"

namespace fleetnav::storage {

absl::StatusOr<uint32_t> SqlMarkerSetRepository::PutMarkerSet(const MarkerSet& markers,
                                                              int64_t created_unix_ms) {
  uint32_t version = 0;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(version, NextVersion(db_, "marker_sets", "map_id", markers.map_id));
    ASSIGN_OR_RETURN(SqlStatement insert,
                     db_->Prepare("INSERT INTO marker_sets (map_id, version, yaml, "
                                  "created_unix_ms) VALUES (?, ?, ?, ?)"));
    insert.Bind(1, markers.map_id)
        .Bind(2, static_cast<int64_t>(version))
        .Bind(3, MarkerSetToYaml(markers))
        .Bind(4, created_unix_ms);
    return insert.Run();
  }));
  return version;
}

absl::StatusOr<StoredMarkerSet> SqlMarkerSetRepository::GetMarkerSet(const std::string& map_id,
                                                                     uint32_t version) {
  std::optional<StoredMarkerSet> found;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(
        SqlStatement query,
        db_->Prepare(version == 0 ? "SELECT version, yaml, created_unix_ms FROM marker_sets WHERE "
                                    "map_id = ? ORDER BY version DESC LIMIT 1"
                                  : "SELECT version, yaml, created_unix_ms FROM marker_sets WHERE "
                                    "map_id = ? AND version = ?"));
    query.Bind(1, map_id);
    if (version != 0) query.Bind(2, static_cast<int64_t>(version));
    ASSIGN_OR_RETURN(bool has_row, query.Step());
    if (!has_row) return absl::OkStatus();
    ASSIGN_OR_RETURN(MarkerSet markers, ParseMarkerSetYaml(query.ColumnText(1)));
    markers.map_id = map_id;
    found = StoredMarkerSet{std::move(markers), static_cast<uint32_t>(query.ColumnInt(0)),
                            query.ColumnInt(2)};
    return absl::OkStatus();
  }));
  if (!found) {
    return absl::NotFoundError(absl::StrCat("marker set of map '", EchoInput(map_id), "'",
                                            version == 0 ? " not found" : "",
                                            VersionText(version)));
  }
  return *std::move(found);
}

absl::Status SqlMarkerSetRepository::DeleteMarkerSet(const std::string& map_id) {
  return DeleteRowsOrNotFound(db_, "DELETE FROM marker_sets WHERE map_id = ?", map_id,
                              absl::StrCat("marker set of map '", EchoInput(map_id), "'"));
}

absl::StatusOr<uint32_t> SqlRouteRepository::PutRoute(const Route& route, int64_t created_unix_ms) {
  uint32_t version = 0;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(version, NextVersion(db_, "routes", "name", route.name));
    ASSIGN_OR_RETURN(SqlStatement insert,
                     db_->Prepare("INSERT INTO routes (name, version, map_id, yaml, "
                                  "created_unix_ms) VALUES (?, ?, ?, ?, ?)"));
    insert.Bind(1, route.name)
        .Bind(2, static_cast<int64_t>(version))
        .Bind(3, route.map_id)
        .Bind(4, RouteToYaml(route))
        .Bind(5, created_unix_ms);
    return insert.Run();
  }));
  return version;
}

absl::StatusOr<StoredRoute> SqlRouteRepository::GetRoute(const std::string& name,
                                                         uint32_t version) {
  std::optional<StoredRoute> found;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(
        SqlStatement query,
        db_->Prepare(version == 0 ? "SELECT version, yaml, created_unix_ms FROM routes WHERE "
                                    "name = ? ORDER BY version DESC LIMIT 1"
                                  : "SELECT version, yaml, created_unix_ms FROM routes WHERE "
                                    "name = ? AND version = ?"));
    query.Bind(1, name);
    if (version != 0) query.Bind(2, static_cast<int64_t>(version));
    ASSIGN_OR_RETURN(bool has_row, query.Step());
    if (!has_row) return absl::OkStatus();
    ASSIGN_OR_RETURN(Route route, ParseRouteYaml(query.ColumnText(1)));
    found = StoredRoute{std::move(route), static_cast<uint32_t>(query.ColumnInt(0)),
                        query.ColumnInt(2)};
    return absl::OkStatus();
  }));
  if (!found) {
    return absl::NotFoundError(absl::StrCat(
        "route '", EchoInput(name), "'", version == 0 ? " not found" : "", VersionText(version)));
  }
  return *std::move(found);
}

absl::StatusOr<std::vector<StoredRoute>> SqlRouteRepository::ListRoutes(const std::string& map_id) {
  std::vector<StoredRoute> out;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement query,
                     db_->Prepare("SELECT version, yaml, created_unix_ms FROM routes r WHERE "
                                  "version = (SELECT MAX(version) FROM routes WHERE name = r.name) "
                                  "AND (? = '' OR map_id = ?) ORDER BY name"));
    query.Bind(1, map_id).Bind(2, map_id);
    while (true) {
      ASSIGN_OR_RETURN(bool has_row, query.Step());
      if (!has_row) break;
      ASSIGN_OR_RETURN(Route route, ParseRouteYaml(query.ColumnText(1)));
      out.push_back(StoredRoute{std::move(route), static_cast<uint32_t>(query.ColumnInt(0)),
                                query.ColumnInt(2)});
    }
    return absl::OkStatus();
  }));
  return out;
}

absl::StatusOr<int> SqlRouteRepository::CountRoutesOnMap(const std::string& map_id) {
  int count = 0;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement query,
                     db_->Prepare("SELECT COUNT(DISTINCT name) FROM routes WHERE map_id = ?"));
    query.Bind(1, map_id);
    ASSIGN_OR_RETURN(bool has_row, query.Step());
    count = has_row ? static_cast<int>(query.ColumnInt(0)) : 0;
    return absl::OkStatus();
  }));
  return count;
}

absl::Status SqlRouteRepository::DeleteRoute(const std::string& name) {
  return DeleteRowsOrNotFound(db_, "DELETE FROM routes WHERE name = ?", name,
                              absl::StrCat("route '", EchoInput(name), "'"));
}

absl::Status SqlRobotRepository::UpsertRobot(const StoredRobot& robot) {
  return db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(
        SqlStatement upsert,
        db_->Prepare("INSERT INTO robots (robot_id, kind_name, capabilities, software_version, "
                     "last_seen_unix_ms) VALUES (?, ?, ?, ?, ?) ON CONFLICT (robot_id) DO UPDATE "
                     "SET kind_name = excluded.kind_name, capabilities = excluded.capabilities, "
                     "software_version = excluded.software_version, "
                     "last_seen_unix_ms = excluded.last_seen_unix_ms"));
    std::string capabilities;
    for (const std::string& c : robot.capabilities) {
      absl::StrAppend(&capabilities, capabilities.empty() ? "" : ",", c);
    }
    upsert.Bind(1, robot.robot_id)
        .Bind(2, robot.kind_name)
        .Bind(3, capabilities)
        .Bind(4, robot.software_version)
        .Bind(5, robot.last_seen_unix_ms);
    return upsert.Run();
  });
}

absl::StatusOr<std::vector<StoredRobot>> SqlRobotRepository::ListRobots() {
  std::vector<StoredRobot> out;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement query,
                     db_->Prepare("SELECT robot_id, kind_name, capabilities, software_version, "
                                  "last_seen_unix_ms FROM robots ORDER BY robot_id"));
    while (true) {
      ASSIGN_OR_RETURN(bool has_row, query.Step());
      if (!has_row) break;
      StoredRobot robot{
          query.ColumnText(0), query.ColumnText(1), {}, query.ColumnText(3), query.ColumnInt(4)};
      const std::string capabilities = query.ColumnText(2);
      size_t start = 0;
      while (start < capabilities.size()) {
        size_t comma = capabilities.find(',', start);
        if (comma == std::string::npos) comma = capabilities.size();
        robot.capabilities.push_back(capabilities.substr(start, comma - start));
        start = comma + 1;
      }
      out.push_back(std::move(robot));
    }
    return absl::OkStatus();
  }));
  return out;
}

absl::Status SqlRobotRepository::DeleteRobot(const std::string& robot_id) {
  return db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement remove, db_->Prepare("DELETE FROM robots WHERE robot_id = ?"));
    remove.Bind(1, robot_id);
    RETURN_IF_ERROR(remove.Run());
    if (db_->ChangedRows() == 0) {
      return absl::NotFoundError(absl::StrCat("robot '", EchoInput(robot_id), "' not found"));
    }
    return absl::OkStatus();
  });
}

}  // namespace fleetnav::storage
