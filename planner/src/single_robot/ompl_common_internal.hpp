#pragma once

// Shared pieces of the OMPL-based planners: a per-instance seeded SE(2) sampler, the costmap's
// footprint test as OMPL validity and motion checkers, RRTConnect with a seeded generator and
// access to its start tree, and the solve → simplify → PathResult pipeline.

#include <ompl/base/MotionValidator.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateSampler.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>

#include <functional>
#include <memory>
#include <stop_token>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/single_robot/ompl_planner_params.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"

namespace fleetnav::planner::internal {

/// Uniform SE(2) samples inside the space's bounds from a generator seeded per instance
/// (OMPL's own samplers draw their seeds from a process-wide generator).
class SeededSe2Sampler : public ompl::base::StateSampler {
 public:
  SeededSe2Sampler(const ompl::base::StateSpace* space, uint32_t seed);
  void sampleUniform(ompl::base::State* state) override;
  void sampleUniformNear(ompl::base::State* state, const ompl::base::State* near,
                         double distance) override;
  void sampleGaussian(ompl::base::State* state, const ompl::base::State* mean,
                      double std_dev) override;

 private:
  void Clamp(ompl::base::SE2StateSpace::StateType* s) const;
};

/// The costmap's footprint test as OMPL state validity.
class FootprintValidityChecker : public ompl::base::StateValidityChecker {
 public:
  FootprintValidityChecker(ompl::base::SpaceInformation* si, Costmap* costmap)
      : ompl::base::StateValidityChecker(si), costmap_(costmap) {}
  bool isValid(const ompl::base::State* state) const override;

 private:
  Costmap* costmap_;
};

/// Checks a motion by sampling the space's interpolation so that no point of the footprint
/// (within `corner_radius_m` of the reference point) moves more than `step_m` between two
/// footprint tests. SE2 motions are straight lines with the yaw interpolated: a point moves at
/// most |Δp| + r·|Δyaw|. Reeds-Shepp motions (turning_radius_m > 0, the space a
/// ReedsSheppStateSpace) are curves of length L turning by at most L / ρ: a point moves at most
/// L·(1 + r / ρ); the curve is computed once per motion.
class FootprintMotionValidator : public ompl::base::MotionValidator {
 public:
  FootprintMotionValidator(ompl::base::SpaceInformation* si, double step_m, double corner_radius_m,
                           double turning_radius_m);
  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2) const override;
  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2,
                   std::pair<ompl::base::State*, double>& last_valid) const override;

 private:
  // Index of the first invalid sample in 1..steps (0 when the motion is valid).
  int FirstInvalid(const ompl::base::State* s1, const ompl::base::State* s2, int* steps,
                   ompl::base::State* scratch) const;
  double step_m_;
  double corner_radius_m_;
  double turning_radius_m_;
};

/// RRTConnect (Kuffner and LaValle, ICRA 2000) with its generator seeded and the start tree's
/// closest pose to a goal exposed for approximate results.
class SeededRrtConnect : public ompl::geometric::RRTConnect {
 public:
  SeededRrtConnect(const ompl::base::SpaceInformationPtr& si, uint32_t seed);
  /// States from the start to the start-tree state closest to `goal` (empty before solve()).
  std::vector<const ompl::base::State*> ClosestStartTreePath(const ompl::base::State* goal) const;
  /// States in both trees.
  int64_t TreeSize() const;
};

/// One OMPL problem: a fresh state space (SE2StateSpace or ReedsSheppStateSpace; bounds are
/// set from the costmap) and how to turn a solution into poses.
struct OmplProblem {
  std::shared_ptr<ompl::base::SE2StateSpace> space;
  double turning_radius_m = 0.0;  ///< > 0 for Reeds-Shepp
  /// Turns the (simplified) solution into poses joined by the PathResult primitives.
  std::function<std::vector<Pose2>(const ompl::geometric::PathGeometric&)> to_poses;
  const char* name = "ompl";
};

/// Validates the request, plans with seeded RRTConnect under a termination condition that
/// combines the request's time limit and the stop token, simplifies deterministically (OMPL's
/// PathSimplifier::collapseCloseVertices, then a greedy shortcut from each vertex to the
/// farthest one reachable by a valid motion) and converts the result.
absl::StatusOr<PathResult> PlanWithOmpl(const OmplProblem& problem, Costmap* costmap,
                                        const OmplPlannerParams& params, const PathRequest& request,
                                        std::stop_token stop);

/// Sets `state` (an SE2 state) to `pose`.
void SetPose(const Pose2& pose, ompl::base::State* state);
Pose2 GetPose(const ompl::base::State* state);

}  // namespace fleetnav::planner::internal
