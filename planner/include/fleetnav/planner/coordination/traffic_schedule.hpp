#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "fleetnav/planner/grid/swept_cells.hpp"

namespace fleetnav::planner {

/// One robot's job as traffic coordination sees it: the floor each action sweeps, when each
/// action is expected to start (any common time base), and how far the robot has got.
struct ScheduledRoute {
  std::string robot_id;
  std::string job_id;
  std::vector<CellSet> action_cells;
  std::vector<CellSet> action_end_cells;  ///< where the robot stands after each action
  std::vector<double> action_start_s;
  CellSet start_cells;  ///< where the robot stands before its first action
  /// Names these cells for ClearanceDecider's memory: a new id whenever the cells are
  /// predicted again (0: never remembered).
  uint64_t cells_id = 0;
  /// When the caller orders segments of its actions: for each, the first segment of the same
  /// action (empty: each stands alone). A segment that meets a robot standing still (parked,
  /// held, or done with its route) holds the whole of its action, so the robot does not drive
  /// up to one that may have to make way out past it.
  std::vector<int> whole_from;
  int first_unfinished = 0;  ///< actions before it have finished
  int cleared_up_to = -1;    ///< actions up to it were cleared earlier (never taken back)
  /// The robot is part-way through the route although nothing of this schedule is cleared yet
  /// (its way was planned again in the middle of an action).
  bool begun = false;
};

/// Whether the robot has begun the route: cleared into it, or past an action of it. A robot
/// that has not stands at its start, so its job can still be withdrawn.
inline bool RouteBegun(const ScheduledRoute& route) {
  return route.begun || route.first_unfinished > 0 || route.cleared_up_to >= 0;
}

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
  bool deadlocked = false;         ///< the routes block each other at action granularity
};

/// Traffic coordination over swept regions with an action dependency graph (Hönig, Kiesel,
/// Tinka, Durham and Ayanian, "Persistent and Robust Execution of MAPF Schedules in
/// Warehouses", RA-L 2019). An "action" here is whatever the caller orders: a route's actions,
/// or segments of them a metre or two long. For two routes A and B, the pairs of unfinished
/// actions whose regions meet (swept cells or where the robot stands after one) form blocks
/// (4-connected components in the grid of action pairs): a block is one place the two robots
/// share, A through actions k1..k2 and B through l1..l2. One robot passes the block first, and
/// the other follows it through: B's action l waits for the last of A's actions in the block
/// that meets l or where B stands after l (or the other way round), so B enters the block as
/// soon as A has left what B's first action needs, and stays one region behind A. Who goes first: a
/// robot already cleared into the block, unless the other stands where it has still to go: then
/// the one that stands (holding it could never let the other on), waiting for those of the
/// other's cleared actions that meet its way, unless its way passes where the other stops after
/// them (then it is held); else the one that stands in the block before it starts (it
/// cannot make way); else not the one whose route ends in the block (it would stay there); else the
/// earlier expected start (robot index breaks ties). Orders that cannot be met or close a cycle
/// hold one route whole (deadlocked; its robot stands as parked; of a cycle, not one whose robot
/// stands in the way of another route on it, unless each does): a route its robot has not
/// begun before one part-way through (the first can be withdrawn and its robot sent aside, the
/// second cannot drop its job), else the newest, so the oldest always goes on. Actions that
/// cross a parked robot are never cleared. Clearances only grow. Pure function.
std::vector<TrafficClearanceDecision> DecideClearances(const std::vector<ScheduledRoute>& routes,
                                                       const std::vector<ParkedRobot>& parked);
/// The same over routes held elsewhere (the server keeps one per job), so that none is copied.
std::vector<TrafficClearanceDecision> DecideClearances(
    const std::vector<const ScheduledRoute*>& routes, const std::vector<ParkedRobot>& parked);

/// One place two routes share: actions k1..k2 of the first and l1..l2 of the second, and for
/// each action of one, the last action of the other that it meets (-1: none), so that a robot
/// that goes second can follow the first through the block action by action.
struct SharedBlock {
  int k1 = 0, k2 = 0, l1 = 0, l2 = 0;
  std::vector<int> last_k_meeting_l;  ///< for l1..l2
  std::vector<int> last_l_meeting_k;  ///< for k1..k2
};

/// DecideClearances with a memory: the shared blocks of each pair of routes are kept from one
/// call to the next while both routes keep their cells (ScheduledRoute::cells_id) and their
/// first unfinished actions, so a pass over a fleet whose routes did not change costs a lookup
/// per pair of nearby routes instead of a cell comparison per pair of actions. Pairs not met in
/// a call are forgotten. Same decisions as DecideClearances. Not thread-safe.
class ClearanceDecider {
 public:
  std::vector<TrafficClearanceDecision> Decide(const std::vector<const ScheduledRoute*>& routes,
                                               const std::vector<ParkedRobot>& parked);
  /// Pairs of routes remembered.
  size_t remembered_pairs() const { return pairs_.size(); }

 private:
  struct Remembered {
    int first_a = 0, first_b = 0;
    std::vector<SharedBlock> blocks;
    uint64_t last_call = 0;
  };
  absl::flat_hash_map<std::pair<uint64_t, uint64_t>, Remembered> pairs_;
  uint64_t calls_ = 0;
};

}  // namespace fleetnav::planner
