#include "fleetnav/planner/single_robot/planner_factory.hpp"

#include <cmath>
#include <string>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/planner/single_robot/ompl_omni_planner.hpp"
#include "fleetnav/planner/single_robot/ompl_reeds_shepp_planner.hpp"

namespace fleetnav::planner {

std::string_view PlannerKindName(PlannerKind kind) {
  switch (kind) {
    case PlannerKind::kLattice:
      return "lattice";
    case PlannerKind::kOmplOmni:
      return "ompl-omni";
    case PlannerKind::kOmplReedsShepp:
      return "ompl-reeds-shepp";
  }
  return "unknown";
}

absl::StatusOr<PlannerKind> PlannerKindByName(std::string_view name) {
  for (PlannerKind kind :
       {PlannerKind::kLattice, PlannerKind::kOmplOmni, PlannerKind::kOmplReedsShepp}) {
    if (PlannerKindName(kind) == name) return kind;
  }
  return absl::InvalidArgumentError(absl::StrCat(
      "kind: '", std::string(name), "' is not lattice, ompl-omni or ompl-reeds-shepp"));
}

SingleRobotPlannerParams NavigationPlannerParams(const RobotModel& model) {
  SingleRobotPlannerParams params;
  params.kind = PlannerKind::kLattice;
  if (model.kinematics == Kinematics::kDifferential) params.lattice = DifferentialLatticeParams();
  if (model.kinematics == Kinematics::kAckermann) params.lattice = CarLatticeParams();
  if (model.kinematics == Kinematics::kOmnidirectional) params.lattice = PlatformLatticeParams();
  return params;
}

absl::StatusOr<std::unique_ptr<SingleRobotPlanner>> MakeSingleRobotPlanner(
    Costmap* costmap, const RobotModel& model, const SingleRobotPlannerParams& params) {
  if (params.kind == PlannerKind::kLattice) {
    return MakeSingleRobotPlanner(costmap, model, params.lattice);
  }
  if (costmap == nullptr) return absl::InvalidArgumentError("costmap: null");
  if (absl::Status s = params.ompl.Validate(); !s.ok()) return s;
  if (absl::Status s = model.Validate(); !s.ok()) return s;
  if (params.kind == PlannerKind::kOmplOmni) {
    if (model.kinematics != Kinematics::kOmnidirectional) {
      return absl::InvalidArgumentError(
          absl::StrCat("kind: ompl-omni needs an omnidirectional model, not ",
                       std::string(KinematicsName(model.kinematics))));
    }
    return std::make_unique<OmplOmniPlanner>(costmap, params.ompl);
  }
  if (model.kinematics != Kinematics::kAckermann) {
    return absl::InvalidArgumentError(
        absl::StrCat("kind: ompl-reeds-shepp needs an Ackermann model, not ",
                     std::string(KinematicsName(model.kinematics))));
  }
  if (!(model.limits.max_steering_rad > 0.0 && model.limits.max_steering_rad < kPi / 2 &&
        model.wheelbase_m > 0.0)) {
    return absl::InvalidArgumentError(
        "model: Ackermann needs wheelbase_m > 0 and max_steering_rad in (0, pi/2)");
  }
  if (!(model.limits.max_reverse_speed_mps > 0.0)) {
    return absl::InvalidArgumentError(
        "kind: ompl-reeds-shepp reverses, but the model's max_reverse_speed_mps is 0");
  }
  return std::make_unique<OmplReedsSheppPlanner>(
      costmap, model.wheelbase_m / std::tan(model.limits.max_steering_rad), params.ompl);
}

}  // namespace fleetnav::planner
