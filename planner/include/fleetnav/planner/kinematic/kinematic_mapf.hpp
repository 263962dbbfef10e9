#pragma once

#include <array>
#include <cstdint>
#include <stop_token>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/planner/grid/movingai.hpp"

namespace fleetnav::planner {

/// Grid directions, counter-clockwise from +x: a heading or a move.
enum GridDirection : int { kPlusX = 0, kPlusY = 1, kMinusX = 2, kMinusY = 3 };

/// How one robot kind moves on the site grid. A value type.
struct GridMotionModel {
  /// With a heading the state is (cell, direction): the robot moves along its heading (and
  /// against it only when `may_reverse`) and turns in place a quarter turn per step. Without
  /// one it moves in any of the four directions (an omnidirectional platform).
  bool has_heading = false;
  bool may_reverse = true;
  /// Cells covered by the robot relative to its cell, given for heading kPlusX; they turn with
  /// the heading. Must contain (0, 0).
  std::vector<std::array<int, 2>> footprint_cells = {{0, 0}};
  /// A lane graph: per cell (row-major) a bit mask of the directions a move out of that cell
  /// may take (bit d for GridDirection d). Empty: every direction everywhere.
  std::vector<uint8_t> allowed_moves;
};

/// One robot of a KinematicMapfProblem.
struct GridRobot {
  int start_x = 0;
  int start_y = 0;
  int start_heading = kPlusX;
  int goal_x = 0;
  int goal_y = 0;
  int goal_heading = -1;  ///< −1: any heading
  GridMotionModel motion;
};

/// A robot's state at one step.
struct GridState {
  int x = 0;
  int y = 0;
  int heading = kPlusX;  ///< kPlusX for robots without a heading
  bool operator==(const GridState&) const = default;
};

/// Heterogeneous multi-robot coordination on a grid site: each robot has its own motion model
/// (heading or not, reversing or not, lanes) and footprint. A plan gives every robot's state at
/// every step from 0; after its last state a robot stays there. Robots must never overlap: at a
/// step each covers its footprint, and while moving from one state to the next it covers both
/// footprints (so no robot enters cells another is still leaving — no following, hence no
/// rotations, and robust to small timing errors).
struct KinematicMapfProblem {
  const MovingAiMap* map = nullptr;
  std::vector<GridRobot> robots;

  /// InvalidArgument naming the robot and field: a footprint off the map or on an obstacle at
  /// the start or goal, a bad heading, a lane mask of the wrong size, two starts overlapping.
  absl::Status Validate() const;
};

/// A plan: states[i][t].
struct KinematicMapfPlan {
  std::vector<std::vector<GridState>> states;
};

/// Row-major indices of the map cells a robot with `motion` covers in state `s`; false when a
/// cell is off the map or blocked (the cells found so far are still returned).
bool CoveredCells(const MovingAiMap& map, const GridMotionModel& motion, const GridState& s,
                  std::vector<int>* cells);

/// Checks a plan against the problem: starts and goals, every transition a move the robot's
/// model allows (lanes included), footprints on free cells, and no two robots overlapping at a
/// step or during a move. InvalidArgument naming the robots and step.
absl::Status ValidateKinematicPlan(const KinematicMapfProblem& problem,
                                   const KinematicMapfPlan& plan);

/// Parameters of PlanKinematicMapf. The search's budget is work (nodes, orders), so a plan does
/// not depend on how busy the machine is; `time_limit_s` is a safety net that ends the search
/// with DeadlineExceeded, never with a different plan.
struct KinematicMapfParams {
  double time_limit_s = 10.0;     ///< > 0; a safety net, not the budget
  uint64_t seed = 0;              ///< priority orders after the first
  int max_steps = 2000;           ///< longest plan searched, > 0
  int cbs_max_nodes = 2000;       ///< conflict-based search nodes before prioritized planning
  int max_priority_orders = 200;  ///< prioritized planning attempts, > 0
};

/// Plans every robot of a heterogeneous problem. Each robot is searched by space-time A* over
/// its own (cell, heading, step) states with an exact static heuristic (a backward breadth-first
/// search over its states from its goal); reservations are kept per cell and half step (states
/// at even, moves at odd half steps), so footprints of any shape are checked cell by cell. Up to
/// 12 robots: conflict-based search (Sharon et al., AIJ 2015; a conflict on cell c at half step
/// h branches into "robot a not on c at h" and "robot b not on c at h"),
/// up to `cbs_max_nodes` nodes, optimal for the sum of arrival steps when it finishes. Otherwise,
/// or when it does not finish: prioritized planning (Erdmann and Lozano-Pérez 1987), revised and
/// plain forms alternated as in MapfPlanner::Replan, restarted with random orders until one
/// succeeds or `max_priority_orders` have failed. Every returned plan passes
/// ValidateKinematicPlan. Errors: InvalidArgument (bad problem or unreachable goal),
/// ResourceExhausted (the work budget ran out), DeadlineExceeded (the safety net), Cancelled.
absl::StatusOr<KinematicMapfPlan> PlanKinematicMapf(const KinematicMapfProblem& problem,
                                                    const KinematicMapfParams& params,
                                                    std::stop_token stop = {});

}  // namespace fleetnav::planner
