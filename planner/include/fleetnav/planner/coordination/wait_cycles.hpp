#pragma once

#include <string>
#include <vector>

#include "fleetnav/planner/coordination/traffic_schedule.hpp"

namespace fleetnav::planner {

/// Robots whose waits close a circle: none of them can move until another of them has, so
/// they stand for ever unless one is given other work (a deadlock of the fleet, not of one
/// pair of routes, which DecideClearances already holds apart).
///
/// The wait-for graph has an edge from a robot to each robot its next held action waits for
/// (TrafficClearanceDecision::waits), when that robot cannot get there by itself: it stands
/// there (blocker_action < 0) or the action waited for lies beyond what it is cleared to do.
/// Robots without a decision (parked: they can be sent aside) have no edges, so they close no
/// circle. Each strongly connected component of two or more robots (Tarjan) is one answer,
/// its robots in the order of `decisions`; components in the order of their first robot.
/// Pure function.
std::vector<std::vector<std::string>> FindWaitCycles(
    const std::vector<TrafficClearanceDecision>& decisions);

}  // namespace fleetnav::planner
