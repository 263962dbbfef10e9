#pragma once

#include <functional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/robot_stop.hpp"
#include "fleetnav/server/site/zone_catalog.hpp"
#include "fleetnav/storage/stop_repository.hpp"

namespace fleetnav::server {

/// Operators' stops (issue 39): a stop of the whole fleet or of one zone is checked (the zone
/// is one of its map's latest zones; a name found on several maps needs the map), stored with
/// the zone's outline, and told to every connected robot at once, as is its clearing (a robot
/// that connects is told the stops in force with its welcome, RobotSessions::StopsInForce). The
/// store is the only state: after a restart or a failover the new fleetnavd tells what the store
/// holds. Not a safety-rated emergency stop. Thread-safe as its repository, catalog and mailbox
/// are.
class StopControl {
 public:
  StopControl(storage::StopRepository* stops, ZoneCatalog* zones, const Clock* clock)
      : stops_(stops), zones_(zones), clock_(clock) {}

  /// Told every stop in force after each stop made or cleared (FleetApp: every connected robot
  /// hears the list). Set before the control is shared.
  void SetChangeListener(std::function<void(const std::vector<RobotStop>&)> listener) {
    on_change_ = std::move(listener);
  }

  /// `zone` empty: the whole fleet (then `map_id` must be empty too). InvalidArgument for a
  /// reason over 256 bytes or an ambiguous zone name, NotFound for an unknown zone or map,
  /// AlreadyExists for a scope already stopped.
  absl::StatusOr<RobotStop> Stop(const std::string& map_id, const std::string& zone,
                                 const std::string& reason);
  /// Clears the stop of the scope (found as for Stop, also when its zone has since gone from
  /// the map's zones); NotFound when none is in force.
  absl::StatusOr<RobotStop> Resume(const std::string& map_id, const std::string& zone);
  absl::StatusOr<std::vector<RobotStop>> InForce();

 private:
  /// The map of `zone` when `map_id` is empty: the one map whose latest zones name it.
  absl::StatusOr<std::string> MapOfZone(const std::string& map_id, const std::string& zone);
  void TellEveryRobot();

  storage::StopRepository* stops_;
  ZoneCatalog* zones_;
  const Clock* clock_;
  std::function<void(const std::vector<RobotStop>&)> on_change_;
};

}  // namespace fleetnav::server
