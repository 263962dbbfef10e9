#pragma once

#include <memory>
#include <string_view>

#include "absl/status/statusor.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/single_robot/ompl_planner_params.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"

namespace fleetnav::planner {

/// Which single-robot planner to build.
enum class PlannerKind {
  kLattice,         ///< LatticePlanner, every kinematics kind (the default; the only one for Lely)
  kOmplOmni,        ///< OmplOmniPlanner, omnidirectional models only
  kOmplReedsShepp,  ///< OmplReedsSheppPlanner, Ackermann models that may reverse
};

std::string_view PlannerKindName(PlannerKind kind);
/// "lattice", "ompl-omni" or "ompl-reeds-shepp"; InvalidArgument otherwise.
absl::StatusOr<PlannerKind> PlannerKindByName(std::string_view name);

/// Parameters of MakeSingleRobotPlanner: the kind and each kind's own parameters.
struct SingleRobotPlannerParams {
  PlannerKind kind = PlannerKind::kLattice;
  LatticeParams lattice;
  OmplPlannerParams ompl;
};

/// The planner a robot of `model` navigates with (the agent) and is predicted with
/// (fleetnavd): the lattice, for Ackermann models with CarLatticeParams (clearance costs, so
/// that a car passes a gap in its middle along its axis, and Reeds-Shepp shots to the exact
/// goal yaw), for omnidirectional ones with PlatformLatticeParams (clearance costs), for
/// differential ones (the Lely) with DifferentialLatticeParams (clearance costs, no escape).
SingleRobotPlannerParams NavigationPlannerParams(const RobotModel& model);

/// The planner of `params.kind` for a robot model. InvalidArgument for bad params or model, or
/// a kind that does not fit the model's kinematics (OMPL omni needs an omnidirectional model;
/// Reeds-Shepp an Ackermann model with wheelbase, steering limit and reversing allowed).
absl::StatusOr<std::unique_ptr<SingleRobotPlanner>> MakeSingleRobotPlanner(
    Costmap* costmap, const RobotModel& model, const SingleRobotPlannerParams& params);

}  // namespace fleetnav::planner
