#pragma once

#include <stop_token>

#include "absl/status/statusor.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/single_robot/ompl_planner_params.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"

namespace fleetnav::planner {

/// An Ackermann planner on OMPL 1.5: ReedsSheppStateSpace (Reeds and Shepp, Pacific J. Math.
/// 1990: shortest paths of a car driving forward and in reverse) with the model's minimum
/// turning radius wheelbase_m / tan(max_steering_rad), RRTConnect and the same deterministic
/// simplification and seeding as OmplOmniPlanner (see there). OMPL's Dubins space is not used:
/// it aborts in Debian's build. The result is the Reeds-Shepp curves sampled about every cell
/// with every segment end (and so every cusp, where the car changes direction) kept: consecutive
/// poses are joined by a straight line or an arc of the turning radius, forward or reverse.
/// The model must allow reversing (max_reverse_speed_mps > 0). Holds a pointer to the costmap,
/// which must outlive it. Not thread-safe.
class OmplReedsSheppPlanner : public SingleRobotPlanner {
 public:
  OmplReedsSheppPlanner(Costmap* costmap, double turning_radius_m, const OmplPlannerParams& params)
      : costmap_(costmap), turning_radius_m_(turning_radius_m), params_(params) {}
  absl::StatusOr<PathResult> Plan(const PathRequest& request, std::stop_token stop = {}) override;
  double turning_radius_m() const { return turning_radius_m_; }

 private:
  Costmap* costmap_;
  double turning_radius_m_;
  OmplPlannerParams params_;
};

}  // namespace fleetnav::planner
