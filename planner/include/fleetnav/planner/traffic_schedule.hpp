#pragma once

#include <string>
#include <vector>

#include "fleetnav/planner/swept_cells.hpp"

namespace fleetnav::planner {

/// One robot's job as traffic coordination sees it: the floor each action sweeps, when each
/// action is expected to start (any common time base), and how far the robot has got.
struct ScheduledRoute {
  std::string robot_id;
  std::string job_id;
  std::vector<CellSet> action_cells;
  std::vector<double> action_start_s;
  CellSet start_cells;  ///< where the robot stands before its first action
  CellSet end_cells;    ///< where it stays after its last action
  int first_unfinished = 0;  ///< actions before it have finished
  int cleared_up_to = -1;    ///< actions up to it were cleared earlier (never taken back)
};

/// A robot with no job on the site: the floor it stands on.
struct ParkedRobot {
  std::string robot_id;
  CellSet cells;
};

/// "Action `action` of `robot_id` may start only when `blocker_action` of `blocker_robot_id`
/// has finished" (-1: never, the blocker is parked there).
struct TrafficWait {
  std::string robot_id;
  int action = 0;
  std::string blocker_robot_id;
  int blocker_action = -1;
};

/// What each robot may do now: the last action it may enter, and what holds the next one.
struct TrafficClearanceDecision {
  std::string robot_id;
  std::string job_id;
  int cleared_up_to = -1;
  std::vector<TrafficWait> waits;  ///< of action cleared_up_to + 1; empty when nothing holds it
  bool deadlocked = false;  ///< the routes block each other at action granularity
};

/// Traffic coordination over swept regions with an action dependency graph (Hönig, Kiesel,
/// Tinka, Durham and Ayanian, "Persistent and Robust Execution of MAPF Schedules in
/// Warehouses", RA-L 2019): two actions of different robots whose swept cells intersect are
/// ordered, and the later one depends on the earlier one finishing. Order: actions already
/// cleared first; then by expected start time, robot index and action index — a total order
/// that is monotone along each route, so the graph is acyclic and no delay of any size can
/// deadlock it. Two constraints come first: an action crossing where a robot stands before
/// its first action waits for that first action, and an action crossing where a robot will
/// stay after its route runs before that robot's last action. A route whose constraints close
/// a cycle is held whole (deadlocked, newest route first) and stands as parked. Actions that
/// cross a parked robot are never cleared. Clearances only grow. Pure function.
std::vector<TrafficClearanceDecision> DecideClearances(const std::vector<ScheduledRoute>& routes,
                                                       const std::vector<ParkedRobot>& parked);

}  // namespace fleetnav::planner
