#include <optional>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_split.h"
#include "delete_rows_internal.hpp"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/sql/sql_fleet_repositories.hpp"

namespace fleetnav::storage {
namespace {

// A polygon as "x y;x y;…" with every digit a double needs to read back the same.
std::string PolygonText(const Polygon2& polygon) {
  std::string text;
  for (const Eigen::Vector2d& vertex : polygon) {
    absl::StrAppend(&text, text.empty() ? "" : ";",
                    absl::StrFormat("%.17g %.17g", vertex.x(), vertex.y()));
  }
  return text;
}

absl::StatusOr<Polygon2> ParsePolygonText(const std::string& text) {
  Polygon2 polygon;
  if (text.empty()) return polygon;
  for (absl::string_view vertex : absl::StrSplit(text, ';')) {
    std::vector<absl::string_view> xy = absl::StrSplit(vertex, ' ');
    double x = 0.0, y = 0.0;
    if (xy.size() != 2 || !absl::SimpleAtod(xy[0], &x) || !absl::SimpleAtod(xy[1], &y)) {
      return absl::DataLossError(absl::StrCat("a stored stop's polygon is damaged: '", text, "'"));
    }
    polygon.emplace_back(x, y);
  }
  return polygon;
}

std::string ScopeText(const std::string& map_id, const std::string& zone) {
  RobotStop scope;
  scope.map_id = map_id;
  scope.zone = zone;
  return scope.Describe();
}

}  // namespace

absl::Status SqlStopRepository::PutStop(const RobotStop& stop) {
  return db_->Transaction([&]() -> absl::Status {
    RETURN_IF_ERROR(db_->LockKey(absl::StrCat("stops:", stop.map_id, "/", stop.zone)));
    ASSIGN_OR_RETURN(SqlStatement existing,
                     db_->Prepare("SELECT 1 FROM stops WHERE map_id = ? AND zone = ?"));
    existing.Bind(1, stop.map_id).Bind(2, stop.zone);
    ASSIGN_OR_RETURN(const bool stopped, existing.Step());
    if (stopped) {
      return absl::AlreadyExistsError(
          absl::StrCat("a stop of ", EchoInput(stop.Describe()), " is already in force"));
    }
    ASSIGN_OR_RETURN(SqlStatement insert,
                     db_->Prepare("INSERT INTO stops (map_id, zone, polygon, reason, "
                                  "created_unix_ms) VALUES (?, ?, ?, ?, ?)"));
    insert.Bind(1, stop.map_id)
        .Bind(2, stop.zone)
        .Bind(3, PolygonText(stop.polygon_in_map))
        .Bind(4, stop.reason)
        .Bind(5, stop.created_unix_ms);
    return insert.Run();
  });
}

absl::Status SqlStopRepository::DeleteStop(const std::string& map_id, const std::string& zone) {
  return db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement remove,
                     db_->Prepare("DELETE FROM stops WHERE map_id = ? AND zone = ?"));
    remove.Bind(1, map_id).Bind(2, zone);
    RETURN_IF_ERROR(remove.Run());
    if (db_->ChangedRows() == 0) {
      return absl::NotFoundError(
          absl::StrCat("no stop of ", EchoInput(ScopeText(map_id, zone)), " is in force"));
    }
    return absl::OkStatus();
  });
}

absl::StatusOr<std::vector<RobotStop>> SqlStopRepository::ListStops() {
  std::vector<RobotStop> out;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement query,
                     db_->Prepare("SELECT map_id, zone, polygon, reason, created_unix_ms FROM "
                                  "stops ORDER BY created_unix_ms, map_id, zone"));
    while (true) {
      ASSIGN_OR_RETURN(bool has_row, query.Step());
      if (!has_row) break;
      RobotStop stop;
      stop.map_id = query.ColumnText(0);
      stop.zone = query.ColumnText(1);
      ASSIGN_OR_RETURN(stop.polygon_in_map, ParsePolygonText(query.ColumnText(2)));
      stop.reason = query.ColumnText(3);
      stop.created_unix_ms = query.ColumnInt(4);
      out.push_back(std::move(stop));
    }
    return absl::OkStatus();
  }));
  return out;
}

}  // namespace fleetnav::storage
