#include "fleetnav/server/site/site_catalog.hpp"

#include "absl/container/flat_hash_set.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/server/site/map_catalog.hpp"

namespace fleetnav::server {
namespace {

absl::Status CheckPointFree(const OccupancyGrid& grid, const Eigen::Vector2d& point, int index,
                            const std::string& action, const std::string& what) {
  const std::string where = absl::StrCat("actions[", index, "] (", action, "): ", what,
                                         absl::StrFormat(" (%.2f, %.2f)", point.x(), point.y()));
  if (!grid.ContainsWorld(point)) return absl::InvalidArgumentError(where + " is outside the map");
  const std::optional<CellIndex> cell = grid.WorldToCell(point);
  if (!cell || grid.State(*cell) != CellState::kFree) {
    return absl::InvalidArgumentError(where + " is not on a free cell of the map");
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status SiteCatalog::ValidateRouteName(const std::string& name) {
  bool ok = !name.empty() && name.size() <= 64;
  for (char c : name) {
    ok = ok && ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                c == '_' || c == '-' || c == '.');
  }
  if (!ok) {
    return absl::InvalidArgumentError(absl::StrCat(
        "route.name: must be 1-64 characters of [A-Za-z0-9_.-], got '", EchoInput(name), "'"));
  }
  return absl::OkStatus();
}

absl::StatusOr<uint32_t> SiteCatalog::PutMarkerSet(const MarkerSet& markers) {
  RETURN_IF_ERROR(MapCatalog::ValidateMapId(markers.map_id));
  RETURN_IF_ERROR(limits_.CheckMarkers(markers));
  RETURN_IF_ERROR(markers.Validate());
  RETURN_IF_ERROR(site_data_->LatestMapVersion(markers.map_id).status());
  absl::StatusOr<uint32_t> version;
  // The same content again is the version that holds it, not a new one.
  if (absl::StatusOr<std::shared_ptr<const storage::StoredMarkerSet>> latest =
          site_data_->MarkerSetVersion(markers.map_id, 0);
      latest.ok() && MarkerSetToYaml((*latest)->markers) == MarkerSetToYaml(markers)) {
    version = (*latest)->version;
  } else {
    version = site_data_->PutMarkerSet(markers, clock_->UnixMs());
  }
  if (version.ok() && on_marker_change_) on_marker_change_(markers.map_id);
  return version;
}

absl::StatusOr<std::shared_ptr<const storage::StoredMarkerSet>> SiteCatalog::GetMarkerSet(
    const std::string& map_id, uint32_t version) {
  RETURN_IF_ERROR(MapCatalog::ValidateMapId(map_id));
  return site_data_->MarkerSetVersion(map_id, version);
}

uint32_t SiteCatalog::LatestMarkerSetVersion(const std::string& map_id) {
  return site_data_->LatestMarkerSetVersion(map_id);
}

absl::Status SiteCatalog::CheckRouteAgainstSite(const Route& route) {
  ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredMap> map, site_data_->Map(route.map_id, 0));
  // Marker ids of the latest set, hashed once: a route may name many of a large set.
  absl::flat_hash_set<int> marker_ids;
  absl::flat_hash_set<std::string> trolley_ids;
  if (absl::StatusOr<std::shared_ptr<const storage::StoredMarkerSet>> markers =
          site_data_->MarkerSetVersion(route.map_id, 0);
      markers.ok()) {
    for (const StripeMarker& marker : (*markers)->markers.markers) marker_ids.insert(marker.id);
    for (const TrolleyPlacement& t : (*markers)->markers.trolleys) trolley_ids.insert(t.id);
  }
  for (size_t i = 0; i < route.actions.size(); ++i) {
    const RouteAction& action = route.actions[i];
    const std::string type(ActionTypeName(action.params));
    const int index = static_cast<int>(i);
    if (action.end.kind == EndConditionKind::kMarkerDetected &&
        !marker_ids.contains(action.end.marker_id)) {
      return absl::InvalidArgumentError(absl::StrCat("actions[", index, "] (", type,
                                                     "): unknown marker ", action.end.marker_id,
                                                     " on map '", route.map_id, "'"));
    }
    if (const auto* dock = std::get_if<DockAction>(&action.params);
        dock != nullptr && dock->target == DockTarget::kTrolley &&
        !trolley_ids.contains(dock->target_id)) {
      return absl::InvalidArgumentError(absl::StrCat("actions[", index, "] (", type,
                                                     "): unknown trolley '", dock->target_id,
                                                     "' on map '", route.map_id, "'"));
    }
    if (const auto* nav = std::get_if<FreeNavigationAction>(&action.params)) {
      for (const Eigen::Vector2d& waypoint : nav->waypoints_m) {
        RETURN_IF_ERROR(CheckPointFree(map->grid, waypoint, index, type, "waypoint"));
      }
      RETURN_IF_ERROR(CheckPointFree(map->grid, nav->goal.translation(), index, type, "goal"));
    }
  }
  return absl::OkStatus();
}

uint32_t SiteCatalog::LatestZoneSetVersion(const std::string& map_id) {
  if (zones_ == nullptr) return 0;
  const std::shared_ptr<const storage::StoredZoneSet> zones = zones_->Latest(map_id);
  return zones != nullptr ? zones->version : 0;
}

absl::Status SiteCatalog::CheckOutsideNoGo(const std::string& map_id, const Eigen::Vector2d& point,
                                           const std::string& field) {
  if (zones_ == nullptr) return absl::OkStatus();
  const std::shared_ptr<const storage::StoredZoneSet> zones = zones_->Latest(map_id);
  return server::CheckOutsideNoGo(zones != nullptr ? &zones->zones : nullptr, point, field);
}

absl::Status SiteCatalog::CheckRouteOutsideNoGo(const Route& route) {
  if (zones_ == nullptr) return absl::OkStatus();
  const std::shared_ptr<const storage::StoredZoneSet> zones = zones_->Latest(route.map_id);
  if (zones == nullptr) return absl::OkStatus();
  for (size_t i = 0; i < route.actions.size(); ++i) {
    const auto* nav = std::get_if<FreeNavigationAction>(&route.actions[i].params);
    if (nav == nullptr) continue;
    const std::string type(ActionTypeName(route.actions[i].params));
    const std::string where = absl::StrCat("actions[", i, "] (", type, "): ");
    for (const Eigen::Vector2d& waypoint : nav->waypoints_m) {
      RETURN_IF_ERROR(server::CheckOutsideNoGo(&zones->zones, waypoint, where + "waypoint"));
    }
    RETURN_IF_ERROR(
        server::CheckOutsideNoGo(&zones->zones, nav->goal.translation(), where + "goal"));
  }
  return absl::OkStatus();
}

absl::StatusOr<uint32_t> SiteCatalog::PutRoute(const Route& route) {
  RETURN_IF_ERROR(ValidateRouteName(route.name));
  RETURN_IF_ERROR(MapCatalog::ValidateMapId(route.map_id));
  RETURN_IF_ERROR(limits_.CheckRoute(route));
  RETURN_IF_ERROR(route.Validate());
  RETURN_IF_ERROR(CheckRouteAgainstSite(route));
  RETURN_IF_ERROR(CheckRouteOutsideNoGo(route));
  // The same content again is the version that holds it, not a new one.
  if (absl::StatusOr<std::shared_ptr<const storage::StoredRoute>> latest =
          site_data_->RouteVersion(route.name, 0);
      latest.ok() && RouteToYaml((*latest)->route) == RouteToYaml(route)) {
    return (*latest)->version;
  }
  return site_data_->PutRoute(route, clock_->UnixMs());
}

absl::StatusOr<std::shared_ptr<const storage::StoredRoute>> SiteCatalog::GetRoute(
    const std::string& name, uint32_t version) {
  RETURN_IF_ERROR(ValidateRouteName(name));
  return site_data_->RouteVersion(name, version);
}

absl::StatusOr<std::vector<storage::StoredRoute>> SiteCatalog::ListRoutes(
    const std::string& map_id) {
  if (!map_id.empty()) RETURN_IF_ERROR(MapCatalog::ValidateMapId(map_id));
  return site_data_->ListRoutes(map_id);
}

absl::StatusOr<std::optional<std::string>> SiteCatalog::UnfinishedJobOnMap(
    const std::string& map_id) {
  storage::JobFilter active;
  active.map_id = map_id;
  active.states = {JobState::kQueued, JobState::kAssigned, JobState::kRunning, JobState::kPaused};
  active.page_size = 1;
  ASSIGN_OR_RETURN(storage::JobPage page, jobs_->ListJobs(active));
  if (page.jobs.empty()) return std::nullopt;
  return page.jobs[0].job_id;
}

absl::Status SiteCatalog::DeleteMarkerSet(const std::string& map_id) {
  RETURN_IF_ERROR(MapCatalog::ValidateMapId(map_id));
  RETURN_IF_ERROR(site_data_->MarkerSetVersion(map_id, 0).status());
  ASSIGN_OR_RETURN(std::vector<storage::StoredRoute> routes, site_data_->ListRoutes(map_id));
  for (const storage::StoredRoute& stored : routes) {
    for (const RouteAction& action : stored.route.actions) {
      if (action.end.kind == EndConditionKind::kMarkerDetected ||
          std::holds_alternative<StripeNavigationAction>(action.params)) {
        return absl::FailedPreconditionError(absl::StrCat(
            "the markers of map '", map_id, "' are used by route '", stored.route.name, "'"));
      }
    }
  }
  ASSIGN_OR_RETURN(std::optional<std::string> job_id, UnfinishedJobOnMap(map_id));
  if (job_id) {
    return absl::FailedPreconditionError(
        absl::StrCat("the markers of map '", map_id, "' are used by unfinished job ", *job_id));
  }
  return site_data_->DeleteMarkerSet(map_id);
}

absl::Status SiteCatalog::DeleteRoute(const std::string& name) {
  RETURN_IF_ERROR(ValidateRouteName(name));
  ASSIGN_OR_RETURN(std::shared_ptr<const storage::StoredRoute> latest,
                   site_data_->RouteVersion(name, 0));
  storage::JobFilter unfinished;
  unfinished.map_id = latest->route.map_id;
  unfinished.states = {JobState::kQueued, JobState::kAssigned, JobState::kRunning,
                       JobState::kPaused};
  unfinished.page_size = 1000;
  while (true) {
    ASSIGN_OR_RETURN(storage::JobPage page, jobs_->ListJobs(unfinished));
    for (const Job& job : page.jobs) {
      if (job.route_name == name) {
        return absl::FailedPreconditionError(
            absl::StrCat("route '", name, "' is run by unfinished job ", job.job_id, " (",
                         std::string(JobStateName(job.state)), ")"));
      }
    }
    if (page.next_page_token.empty()) break;
    unfinished.page_token = page.next_page_token;
  }
  return site_data_->DeleteRoute(name);
}

absl::Status SiteCatalog::DeleteMap(const std::string& map_id) {
  RETURN_IF_ERROR(MapCatalog::ValidateMapId(map_id));
  ASSIGN_OR_RETURN(int routes, site_data_->CountRoutesOnMap(map_id));
  if (routes > 0) {
    return absl::FailedPreconditionError(
        absl::StrCat("map '", map_id, "' is used by ", routes, " route(s)"));
  }
  ASSIGN_OR_RETURN(std::optional<std::string> job_id, UnfinishedJobOnMap(map_id));
  if (job_id) {
    return absl::FailedPreconditionError(
        absl::StrCat("map '", map_id, "' is used by unfinished job ", *job_id));
  }
  return site_data_->DeleteMap(map_id);
}

}  // namespace fleetnav::server
