#pragma once

#include <string>
#include <vector>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/core/robot_stop.hpp"

namespace fleetnav::agent {

/// `command` (robot frame) slowed so that the robot stops short of every stopped zone of
/// `map_id`: the speed at which its centre nears a zone (driving `command` for `horizon_s`
/// from `pose_in_map`) is at most sqrt(2·a·gap), where gap is what is left between the zone and
/// its reach (`reach_m`: its body grown by its estimate's uncertainty) and a is
/// `braking_decel_mps2` — the whole command scaled, so that it keeps its path's curvature. So a
/// robot heading into a stopped zone brakes to a stand before its reach meets the zone, while
/// one driving along its edge or away from it (on a way planned round it) drives on.
Twist2 KeepOffStoppedZones(const Twist2& command, const std::vector<RobotStop>& stops,
                           const std::string& map_id, const Pose2& pose_in_map, double reach_m,
                           double braking_decel_mps2, double horizon_s = 0.5);

}  // namespace fleetnav::agent
