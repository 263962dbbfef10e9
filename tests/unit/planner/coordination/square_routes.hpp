#pragma once

// Routes of a 1 m square robot for the traffic-coordination tests: regions swept on 0.25 m
// cells without margin, one action per leg.

#include <string>
#include <vector>

#include "fleetnav/planner/coordination/traffic_schedule.hpp"

namespace fleetnav::planner::testing {

inline const std::vector<Eigen::Vector2d> kSquare{
    {-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}};

/// The cells a 1 m square sweeps from `from` to `to` (no margin, 0.25 m cells).
inline CellSet Line(Eigen::Vector2d from, Eigen::Vector2d to) {
  std::vector<Pose2> poses;
  for (int i = 0; i <= 20; ++i) {
    const Eigen::Vector2d p = from + (to - from) * (i / 20.0);
    poses.emplace_back(p.x(), p.y(), 0.0);
  }
  return CellSet::Sweep(poses, kSquare, 0.0, 0.25);
}

/// Where the square stands at `p`.
inline CellSet At(Eigen::Vector2d p) { return Line(p, p); }

/// A route of legs through `points`, one action per leg, each expected to take 10 s from t0.
inline ScheduledRoute Route(const std::string& robot, std::vector<Eigen::Vector2d> points,
                            double t0) {
  ScheduledRoute r;
  r.robot_id = robot;
  r.job_id = "job-" + robot;
  for (size_t i = 1; i < points.size(); ++i) {
    r.action_cells.push_back(Line(points[i - 1], points[i]));
    r.action_end_cells.push_back(At(points[i]));
    r.action_start_s.push_back(t0 + 10.0 * (i - 1));
  }
  r.start_cells = At(points.front());
  return r;
}

}  // namespace fleetnav::planner::testing
