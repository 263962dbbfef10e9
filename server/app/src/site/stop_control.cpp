#include "fleetnav/server/site/stop_control.hpp"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/server/site/map_catalog.hpp"

namespace fleetnav::server {

absl::StatusOr<std::string> StopControl::MapOfZone(const std::string& map_id,
                                                   const std::string& zone) {
  if (!map_id.empty()) {
    RETURN_IF_ERROR(MapCatalog::ValidateMapId(map_id));
    return map_id;
  }
  ASSIGN_OR_RETURN(std::vector<storage::StoredZoneSet> sets, zones_->ListZones());
  std::vector<std::string> maps;
  for (const storage::StoredZoneSet& set : sets) {
    if (set.zones.Find(zone) != nullptr) maps.push_back(set.zones.map_id);
  }
  // A stop whose zone has gone from the zones can still be found to be cleared.
  ASSIGN_OR_RETURN(std::vector<RobotStop> stops, stops_->ListStops());
  for (const RobotStop& stop : stops) {
    if (stop.zone == zone && std::find(maps.begin(), maps.end(), stop.map_id) == maps.end()) {
      maps.push_back(stop.map_id);
    }
  }
  if (maps.empty()) {
    return absl::NotFoundError(
        absl::StrCat("scope.zone: no map has a zone named '", EchoInput(zone), "'"));
  }
  if (maps.size() > 1) {
    return absl::InvalidArgumentError(absl::StrCat("scope.map_id: zone '", EchoInput(zone),
                                                   "' is on ", maps.size(), " maps; name the map"));
  }
  return maps.front();
}

absl::StatusOr<RobotStop> StopControl::Stop(const std::string& map_id, const std::string& zone,
                                            const std::string& reason) {
  if (reason.size() > 256) {
    return absl::InvalidArgumentError(
        absl::StrCat("reason: at most 256 bytes, got ", reason.size()));
  }
  RobotStop stop;
  stop.reason = reason;
  stop.created_unix_ms = clock_->UnixMs();
  if (zone.empty()) {
    if (!map_id.empty()) {
      return absl::InvalidArgumentError(
          "scope: a whole-fleet stop names no map (give a zone to stop one area)");
    }
  } else {
    ASSIGN_OR_RETURN(stop.map_id, MapOfZone(map_id, zone));
    const std::shared_ptr<const storage::StoredZoneSet> zones = zones_->Latest(stop.map_id);
    const Zone* found = zones != nullptr ? zones->zones.Find(zone) : nullptr;
    if (found == nullptr) {
      return absl::NotFoundError(absl::StrCat("scope.zone: map '", stop.map_id,
                                              "' has no zone named '", EchoInput(zone), "'"));
    }
    stop.zone = zone;
    stop.polygon_in_map = found->polygon_in_map;
  }
  RETURN_IF_ERROR(stops_->PutStop(stop));
  TellEveryRobot();
  return stop;
}

absl::StatusOr<RobotStop> StopControl::Resume(const std::string& map_id, const std::string& zone) {
  std::string map = map_id;
  if (zone.empty() && !map_id.empty()) {
    return absl::InvalidArgumentError("scope: the whole fleet's stop names no map");
  }
  if (!zone.empty()) {
    ASSIGN_OR_RETURN(map, MapOfZone(map_id, zone));
  }
  ASSIGN_OR_RETURN(std::vector<RobotStop> stops, stops_->ListStops());
  RobotStop cleared;
  for (const RobotStop& stop : stops) {
    if (stop.map_id == map && stop.zone == zone) cleared = stop;
  }
  RETURN_IF_ERROR(stops_->DeleteStop(map, zone));
  TellEveryRobot();
  return cleared;
}

absl::StatusOr<std::vector<RobotStop>> StopControl::InForce() { return stops_->ListStops(); }

void StopControl::TellEveryRobot() {
  if (!on_change_) return;
  if (absl::StatusOr<std::vector<RobotStop>> stops = stops_->ListStops(); stops.ok()) {
    on_change_(*stops);
  }
}

}  // namespace fleetnav::server
