#pragma once

#include <optional>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/route.hpp"

namespace fleetnav::agent {

/// What is left of `action` once `fraction_done` of it is done and the robot stands at
/// `pose_in_map`, so that a restarted agent goes on from there instead of driving the action
/// again from its beginning: a turn or a straight by what is left of its angle or distance; a
/// fence or stripe leg by what is left of its distance (a leg that ends on a marker or at the
/// stripe's end keeps `kEndSlackM` beyond it, for its distance only bounds the search); a
/// free-navigation leg without the waypoints already behind the robot (those before the
/// waypoint segment nearest to it); a dock as it is. nullopt when nothing is left of it (the
/// robot goes on with the next action).
std::optional<RouteAction> RemainderOf(const RouteAction& action, double fraction_done,
                                       const Pose2& pose_in_map);

/// Slack kept beyond the expected remainder of a leg whose distance only bounds the search for
/// its end (a marker, the stripe's end): the fraction a restarted agent resumes from is up to
/// one telemetry period old.
inline constexpr double kEndSlackM = 0.5;

}  // namespace fleetnav::agent
