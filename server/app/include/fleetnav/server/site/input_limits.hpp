#pragma once

#include <cstdint>

#include "absl/status/status.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/core/zone.hpp"

namespace fleetnav::server {

/// Bounds on what clients may store or announce, so that no single request can make every later
/// dispatch, telemetry message or watch update expensive. Each is configurable under `limits:` in
/// fleetnavd.yaml; a request beyond one is refused with RESOURCE_EXHAUSTED naming the limit
/// (`limits.max_markers = 100000`) and nothing of it is kept.
struct InputLimits {
  int64_t max_map_cells = 64'000'000;  ///< 8000 × 8000, what the 64 MiB message limit lets in
  int max_markers = 100'000;           ///< per marker set
  int max_zones = 1'000;               ///< per zone set
  int max_zone_vertices = 256;         ///< per zone polygon
  int max_route_actions = 10'000;
  int max_waypoints_per_action = 1'000;
  int max_capabilities = 64;      ///< per robot hello
  int max_footprint_points = 64;  ///< per robot hello
  int max_sensors = 64;           ///< per robot hello
  int max_text_bytes = 256;       ///< a capability, kind name, software version, description

  /// InvalidArgument naming a limit that is not positive.
  absl::Status Validate() const;
  absl::Status CheckMap(const OccupancyGrid& grid) const;
  absl::Status CheckMapDescription(const std::string& description) const;
  absl::Status CheckMarkers(const MarkerSet& markers) const;
  absl::Status CheckZones(const ZoneSet& zones) const;
  absl::Status CheckRoute(const Route& route) const;
  absl::Status CheckIdentity(const RobotIdentity& identity) const;
};

}  // namespace fleetnav::server
