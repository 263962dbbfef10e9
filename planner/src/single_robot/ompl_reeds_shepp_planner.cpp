#include "fleetnav/planner/single_robot/ompl_reeds_shepp_planner.hpp"

#include <ompl/base/spaces/ReedsSheppStateSpace.h>

#include <cmath>

#include "absl/strings/str_cat.h"
#include "ompl_common_internal.hpp"

namespace fleetnav::planner {

absl::StatusOr<PathResult> OmplReedsSheppPlanner::Plan(const PathRequest& request,
                                                       std::stop_token stop) {
  if (!(turning_radius_m_ > 0.0) || !std::isfinite(turning_radius_m_)) {
    return absl::InvalidArgumentError("turning_radius_m: must be finite and > 0");
  }
  namespace ob = ompl::base;
  auto space = std::make_shared<ob::ReedsSheppStateSpace>(turning_radius_m_);
  const double spacing_m = costmap_->resolution_m();
  const double rho = turning_radius_m_;
  internal::OmplProblem problem;
  problem.space = space;
  problem.turning_radius_m = rho;
  problem.name = "ompl-reeds-shepp";
  problem.to_poses = [space, spacing_m, rho](const ompl::geometric::PathGeometric& path) {
    std::vector<const ob::State*> states;
    for (size_t i = 0; i < path.getStateCount(); ++i) states.push_back(path.getState(i));
    std::vector<Pose2> poses;
    if (states.empty()) return poses;
    poses.push_back(internal::GetPose(states[0]));
    ob::State* scratch = space->allocState();
    for (size_t i = 1; i < states.size(); ++i) {
      ob::ReedsSheppStateSpace::ReedsSheppPath rs = space->reedsShepp(states[i - 1], states[i]);
      const double total = rs.length();  // in turning radii
      if (total * rho < 1e-9) continue;  // a repeated state
      double done = 0.0;
      for (int k = 0; k < 5; ++k) {
        const double seg = std::abs(rs.length_[k]);
        if (rs.type_[k] == ob::ReedsSheppStateSpace::RS_NOP || seg < 1e-12) continue;
        const int n = std::max(1, static_cast<int>(std::ceil(seg * rho / spacing_m)));
        for (int j = 1; j <= n; ++j) {
          bool first_time = false;
          space->interpolate(states[i - 1], states[i], (done + seg * j / n) / total, first_time, rs,
                             scratch);
          poses.push_back(internal::GetPose(scratch));
        }
        done += seg;
      }
      // The last sample is the next state up to rounding: use the state itself.
      poses.pop_back();
      poses.push_back(internal::GetPose(states[i]));
    }
    space->freeState(scratch);
    return poses;
  };
  return internal::PlanWithOmpl(problem, costmap_, params_, request, stop);
}

}  // namespace fleetnav::planner
