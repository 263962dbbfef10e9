#include "fleetnav/planner/single_robot/ompl_omni_planner.hpp"

#include "ompl_common_internal.hpp"

namespace fleetnav::planner {

absl::StatusOr<PathResult> OmplOmniPlanner::Plan(const PathRequest& request, std::stop_token stop) {
  internal::OmplProblem problem;
  problem.space = std::make_shared<ompl::base::SE2StateSpace>();
  problem.name = "ompl-omni";
  problem.to_poses = [](const ompl::geometric::PathGeometric& path) {
    std::vector<Pose2> poses;
    for (size_t i = 0; i < path.getStateCount(); ++i) {
      poses.push_back(internal::GetPose(path.getState(i)));
    }
    return poses;
  };
  return internal::PlanWithOmpl(problem, costmap_, params_, request, stop);
}

}  // namespace fleetnav::planner
