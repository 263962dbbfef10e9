#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "fleetnav/core/job.hpp"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/stripe_marker.hpp"

namespace fleetnav::server::http {

/// The live part of the dashboard, pushed several times a second: every robot (pose, the
/// covariance ellipse's half-axes and angle, mode, battery, link state, job, what traffic holds
/// it for) and every unfinished job (state, progress, robot, route, reason).
nlohmann::json FleetStateJson(const std::vector<RobotRecord>& robots, const std::vector<Job>& jobs,
                              int64_t server_unix_ms);

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
