#pragma once

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/robot_agent/mode_factory.hpp"

namespace fleetnav::agent {

struct RouteSiteCheckParams {
  /// A fence leg needs something its ultrasonic would see within its fence distance plus this
  /// margin, at one pose at least along the leg.
  double fence_search_margin_m = 1.0;
  absl::Status Validate() const;
};

/// Checks a route against the site's map from the pose the robot starts at, before it moves
/// (CheckRoute asks whether this robot can run each action; this asks whether the site lets
/// it). The poses of the actions are predicted one after another (planner::PredictRoute, free
/// navigation drawn straight to its goal); where one cannot be predicted (a stripe the marker
/// set does not hold, an end on a marker or on the charger contact) the check stops there. Every
/// fence leg must pass a fence: an obstacle on the map that the leg's ultrasonic beam meets within
/// the fence distance plus a margin at some pose along it. Every free-navigation goal (and
/// waypoint) must be connected to where its leg starts through cells at least the footprint's
/// inscribed radius from any obstacle — a necessary condition of every collision-free path, so a
/// reachable goal is never refused. Without a map there is nothing to check. FailedPrecondition
/// naming the action's index. `first_action` > 0 checks a resumed route from that action on.
absl::Status CheckRouteOnSite(const Route& route, const RouteContext& context,
                              const Pose2& start_in_map, const RouteSiteCheckParams& params = {},
                              int first_action = 0);

}  // namespace fleetnav::agent
