#include "fleetnav/server/site/input_limits.hpp"

#include <string>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::server {
namespace {

absl::Status Exceeds(const std::string& what, int64_t count, const char* limit, int64_t value) {
  return absl::ResourceExhaustedError(
      absl::StrCat(what, ": ", count, " exceeds limits.", limit, " = ", value));
}

absl::Status CheckText(const std::string& field, const std::string& text, int max_bytes) {
  if (static_cast<int64_t>(text.size()) <= max_bytes) return absl::OkStatus();
  return absl::ResourceExhaustedError(
      absl::StrCat(field, ": ", text.size(), " bytes exceeds limits.max_text_bytes = ", max_bytes));
}

}  // namespace

absl::Status InputLimits::Validate() const {
  const std::pair<const char*, int64_t> limits[] = {
      {"max_map_cells", max_map_cells},
      {"max_markers", max_markers},
      {"max_zones", max_zones},
      {"max_zone_vertices", max_zone_vertices},
      {"max_route_actions", max_route_actions},
      {"max_waypoints_per_action", max_waypoints_per_action},
      {"max_capabilities", max_capabilities},
      {"max_footprint_points", max_footprint_points},
      {"max_sensors", max_sensors},
      {"max_text_bytes", max_text_bytes}};
  for (const auto& [name, value] : limits) {
    if (value < 1) {
      return absl::InvalidArgumentError(
          absl::StrCat("limits.", name, ": must be >= 1, got ", value));
    }
  }
  return absl::OkStatus();
}

absl::Status InputLimits::CheckMap(const OccupancyGrid& grid) const {
  const int64_t cells = int64_t{grid.width()} * grid.height();
  if (cells <= max_map_cells) return absl::OkStatus();
  return Exceeds(absl::StrCat("map: ", grid.width(), " × ", grid.height(), " cells"), cells,
                 "max_map_cells", max_map_cells);
}

absl::Status InputLimits::CheckMapDescription(const std::string& description) const {
  return CheckText("description", description, max_text_bytes);
}

absl::Status InputLimits::CheckMarkers(const MarkerSet& markers) const {
  if (static_cast<int64_t>(markers.markers.size()) <= max_markers) return absl::OkStatus();
  return Exceeds("marker_set.markers", static_cast<int64_t>(markers.markers.size()), "max_markers",
                 max_markers);
}

absl::Status InputLimits::CheckZones(const ZoneSet& zones) const {
  if (static_cast<int64_t>(zones.zones.size()) > max_zones) {
    return Exceeds("zone_set.zones", static_cast<int64_t>(zones.zones.size()), "max_zones",
                   max_zones);
  }
  for (size_t i = 0; i < zones.zones.size(); ++i) {
    const auto vertices = static_cast<int64_t>(zones.zones[i].polygon_in_map.size());
    if (vertices > max_zone_vertices) {
      return Exceeds(absl::StrCat("zone_set.zones[", i, "].polygon"), vertices, "max_zone_vertices",
                     max_zone_vertices);
    }
    if (static_cast<int64_t>(zones.zones[i].name.size()) > max_text_bytes) {
      return CheckText(absl::StrCat("zone_set.zones[", i, "].name"), zones.zones[i].name,
                       max_text_bytes);
    }
  }
  return absl::OkStatus();
}

absl::Status InputLimits::CheckRoute(const Route& route) const {
  if (static_cast<int64_t>(route.actions.size()) > max_route_actions) {
    return Exceeds("route.actions", static_cast<int64_t>(route.actions.size()), "max_route_actions",
                   max_route_actions);
  }
  for (size_t i = 0; i < route.actions.size(); ++i) {
    const auto* nav = std::get_if<FreeNavigationAction>(&route.actions[i].params);
    if (nav != nullptr &&
        static_cast<int64_t>(nav->waypoints_m.size()) > max_waypoints_per_action) {
      return Exceeds(absl::StrCat("route.actions[", i, "].waypoints"),
                     static_cast<int64_t>(nav->waypoints_m.size()), "max_waypoints_per_action",
                     max_waypoints_per_action);
    }
  }
  return absl::OkStatus();
}

absl::Status InputLimits::CheckIdentity(const RobotIdentity& identity) const {
  if (static_cast<int64_t>(identity.capabilities.size()) > max_capabilities) {
    return Exceeds("hello.capabilities", static_cast<int64_t>(identity.capabilities.size()),
                   "max_capabilities", max_capabilities);
  }
  if (static_cast<int64_t>(identity.model.footprint_m.size()) > max_footprint_points) {
    return Exceeds("hello.model.footprint", static_cast<int64_t>(identity.model.footprint_m.size()),
                   "max_footprint_points", max_footprint_points);
  }
  if (static_cast<int64_t>(identity.model.sensors.size()) > max_sensors) {
    return Exceeds("hello.model.sensors", static_cast<int64_t>(identity.model.sensors.size()),
                   "max_sensors", max_sensors);
  }
  for (size_t i = 0; i < identity.capabilities.size(); ++i) {
    RETURN_IF_ERROR(CheckText(absl::StrCat("hello.capabilities[", i, "]"), identity.capabilities[i],
                              max_text_bytes));
  }
  RETURN_IF_ERROR(CheckText("hello.model.kind_name", identity.model.kind_name, max_text_bytes));
  return CheckText("hello.software_version", identity.software_version, max_text_bytes);
}

}  // namespace fleetnav::server
