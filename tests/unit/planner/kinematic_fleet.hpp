#pragma once

#include <cstdlib>
#include <random>
#include <vector>

#include "fleetnav/planner/kinematic/kinematic_mapf.hpp"

namespace fleetnav::planner::testing {

/// A robot that drives only along its heading and turns in place (the Lely feeding robot).
inline GridMotionModel ForwardOnly() {
  GridMotionModel m;
  m.has_heading = true;
  m.may_reverse = false;
  return m;
}

/// An omnidirectional platform covering 2 x 2 cells.
inline GridMotionModel Square2x2() {
  GridMotionModel m;
  m.footprint_cells = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  return m;
}

/// A barn alley 12 cells long with a one-cell bay above its middle.
inline MovingAiMap BayAlley() {
  MovingAiMap map;
  map.width = 12;
  map.height = 2;
  map.passable.assign(24, true);
  for (int x = 0; x < 12; ++x) map.passable[x] = x == 5;  // row 0: only the bay
  return map;
}

/// Two forward-only robots at the ends of BayAlley facing each other, each sent to the other's
/// end. The map must outlive the problem.
inline KinematicMapfProblem BaySwap(const MovingAiMap& alley) {
  KinematicMapfProblem problem{&alley, {}};
  problem.robots.push_back({0, 1, kPlusX, 11, 1, -1, ForwardOnly()});
  problem.robots.push_back({11, 1, kMinusX, 0, 1, -1, ForwardOnly()});
  return problem;
}

/// Every move of a forward-only robot goes along its heading.
inline bool NeverReverses(const std::vector<GridState>& states) {
  const int dx[4] = {1, 0, -1, 0}, dy[4] = {0, 1, 0, -1};
  for (size_t t = 1; t < states.size(); ++t) {
    const GridState& a = states[t - 1];
    const GridState& b = states[t];
    if (a.x == b.x && a.y == b.y) continue;
    if (b.x - a.x != dx[a.heading] || b.y - a.y != dy[a.heading]) return false;
  }
  return true;
}

/// Three forward-only robots, three one-cell omni platforms and two 2 x 2 platforms with seeded
/// random starts and goals on `map` (goals at least 3 cells apart in x or y, so a parked robot
/// never covers another's goal). The map must outlive the problem.
inline KinematicMapfProblem RandomMixedFleet(const MovingAiMap& map, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> x_of(0, map.width - 1), y_of(0, map.height - 1);
  KinematicMapfProblem problem{&map, {}};
  const std::vector<GridMotionModel> kinds = {
      ForwardOnly(),     ForwardOnly(),     ForwardOnly(), GridMotionModel{},
      GridMotionModel{}, GridMotionModel{}, Square2x2(),   Square2x2()};
  for (const GridMotionModel& kind : kinds) {
    for (int tries = 0; tries < 1000; ++tries) {
      GridRobot r{x_of(rng), y_of(rng), kPlusX, x_of(rng), y_of(rng), -1, kind};
      if (kind.has_heading) r.start_heading = static_cast<int>(rng() % 4);
      problem.robots.push_back(r);
      std::vector<int> goal_cells;
      const bool goal_fits = CoveredCells(map, kind, {r.goal_x, r.goal_y, kPlusX}, &goal_cells);
      bool goals_apart = true;
      for (size_t j = 0; j + 1 < problem.robots.size(); ++j) {
        goals_apart &= std::abs(problem.robots[j].goal_x - r.goal_x) > 2 ||
                       std::abs(problem.robots[j].goal_y - r.goal_y) > 2;
      }
      if (goal_fits && goals_apart && problem.Validate().ok()) break;
      problem.robots.pop_back();
    }
  }
  return problem;
}

}  // namespace fleetnav::planner::testing
