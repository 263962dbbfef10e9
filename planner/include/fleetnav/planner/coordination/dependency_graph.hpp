#pragma once

#include <vector>

#include "absl/status/status.h"

namespace fleetnav::planner {

/// The structure every action dependency graph shares (Hönig, Kiesel, Tinka, Durham and
/// Ayanian, "Persistent and Robust Execution of MAPF Schedules in Warehouses", RA-L 2019):
/// actions numbered in the order they were added, each robot's actions in execution order
/// (type-1 dependencies: an action waits for the robot's previous one), and for each action the
/// other robots' actions that must be finished before it starts (type 2). A robot that starts
/// an action only when its dependencies are finished never meets another robot and, when the
/// graph is acyclic, never deadlocks. ActionDependencyGraph (grid plans) and
/// KinematicDependencyGraph (kinematic plans) compile plans into one; the server reads it. A
/// value type.
class DependencyGraph {
 public:
  explicit DependencyGraph(int num_robots = 0) : by_robot_(num_robots) {}

  /// Appends an action of `robot` after its previous one and returns the action's id.
  int AddAction(int robot);
  /// Action `after` starts only once `before`, another robot's action, is finished. A
  /// dependency given twice, or on the same robot's action, is ignored; returns whether it was
  /// added.
  bool AddCrossDependency(int before, int after);

  int num_actions() const { return static_cast<int>(robot_of_.size()); }
  int num_robots() const { return static_cast<int>(by_robot_.size()); }
  int num_cross_dependencies() const { return cross_; }
  int RobotOf(int id) const { return robot_of_[id]; }
  /// Position of the action in its robot's sequence (0 for the robot's first).
  int IndexInRobot(int id) const { return index_in_robot_[id]; }
  /// The actions of one robot, in execution order.
  const std::vector<int>& ActionsOf(int robot) const { return by_robot_[robot]; }
  /// The other robots' actions that must be finished before `id` may start.
  const std::vector<int>& CrossDependenciesOf(int id) const { return cross_deps_[id]; }
  /// Every action that must be finished before `id` may start: the robot's previous action
  /// (if any) and the cross dependencies.
  std::vector<int> DependenciesOf(int id) const;
  /// FailedPrecondition naming two robots of a cycle (robots that would wait for each other
  /// for ever); OK when there is none.
  absl::Status CheckAcyclic() const;

 private:
  std::vector<int> robot_of_;
  std::vector<int> index_in_robot_;
  std::vector<std::vector<int>> by_robot_;
  std::vector<std::vector<int>> cross_deps_;
  int cross_ = 0;
};

}  // namespace fleetnav::planner
