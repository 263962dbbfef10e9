#pragma once

#include <ompl/base/Planner.h>

#include <functional>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"

namespace fleetnav::planner {

/// Runs any SingleRobotPlanner as an ompl::base::Planner on an SE2 problem, so that one
/// ompl::tools::Benchmark run times our lattice planners and the OMPL-based ones alike and
/// writes OMPL's benchmark log. Each solve() makes a fresh planner with `make(run)` (run = 0,
/// 1, ...: seeded planners take a different seed per run), plans from the problem's first start
/// state to its goal (an ompl::base::GoalState) with `request`'s tolerances and time limit,
/// stopping when OMPL's termination condition fires, and adds the poses as an SE2 path
/// (approximate when PathResult::exact is false). The last result stays readable for extra run
/// properties. Not thread-safe.
class SingleRobotPlannerAdapter : public ompl::base::Planner {
 public:
  using Factory = std::function<absl::StatusOr<std::unique_ptr<SingleRobotPlanner>>(int run)>;
  SingleRobotPlannerAdapter(const ompl::base::SpaceInformationPtr& si, const std::string& name,
                            Factory make, const PathRequest& request);
  ompl::base::PlannerStatus solve(const ompl::base::PlannerTerminationCondition& ptc) override;
  /// The result of the last solve() (FailedPrecondition before the first).
  const absl::StatusOr<PathResult>& last_result() const { return last_; }

 private:
  Factory make_;
  PathRequest request_;
  int run_ = 0;
  absl::StatusOr<PathResult> last_ = absl::FailedPreconditionError("not run yet");
};

}  // namespace fleetnav::planner
