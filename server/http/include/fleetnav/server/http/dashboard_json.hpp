#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "fleetnav/core/job.hpp"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/core/robot_stop.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/stripe_marker.hpp"

namespace fleetnav::server::http {

/// The live part of the dashboard, pushed several times a second: every robot (pose, the
/// covariance ellipse's half-axes and angle, mode, battery, link state, job, what traffic holds
/// it for), every unfinished job (state, progress, robot, route, reason) and every operator's
/// stop in force (StopsJson).
nlohmann::json FleetStateJson(const std::vector<RobotRecord>& robots, const std::vector<Job>& jobs,
                              const std::vector<RobotStop>& stops, int64_t server_unix_ms);
/// Operators' stops in force: map, zone (both "" for the whole fleet), reason, when made and
/// the zone's outline as stopped.
nlohmann::json StopsJson(const std::vector<RobotStop>& stops);
/// A map's zones for drawing: their version (0: none) and each zone's name, kind (no_go,
/// speed_limit, one_at_a_time), outline, speed limit and capacity.
nlohmann::json ZonesJson(uint32_t version, const ZoneSet* zones);

/// The 1-sigma ellipse of a pose covariance (row-major 3x3 over x, y, yaw): half-axes in
/// metres, the major axis's angle in radians.
struct CovarianceEllipse {
  double major_m = 0.0;
  double minor_m = 0.0;
  double angle_rad = 0.0;
};
CovarianceEllipse EllipseOf(const std::array<double, 9>& covariance);

/// A map for drawing: size, resolution, origin and the cells as map_server greys, row-major
/// from the top row, base64 (one byte per cell: 254 free, 0 occupied, 205 unknown).
nlohmann::json MapJson(const std::string& map_id, uint32_t version, const OccupancyGrid& grid);
/// Markers (position, yaw, length, kind) and routes (name, the map-anchored points of each
/// free-navigation leg and the stripes followed) of one map.
nlohmann::json SiteJson(const MarkerSet* markers, const std::vector<Route>& routes);
/// One job's events, oldest first.
nlohmann::json JobEventsJson(const std::vector<JobEvent>& events);

}  // namespace fleetnav::server::http
