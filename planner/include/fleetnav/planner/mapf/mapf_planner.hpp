#pragma once

#include <cstdint>

#include "absl/status/statusor.h"
#include "fleetnav/planner/mapf/mapf.hpp"
#include "fleetnav/planner/mapf/mapf_solver.hpp"

namespace fleetnav::planner {

/// Parameters of MapfPlanner.
struct MapfPlannerParams {
  enum class Selection { kAuto, kLacam, kEecbs };
  Selection selection = Selection::kAuto;
  uint64_t seed = 0;    ///< passed to every randomized solver
  bool anytime = true;  ///< refine by large neighbourhood search while time remains
  /// kAuto tries EECBS first when there are at most this many agents.
  int eecbs_max_agents = 100;
  /// Share of the budget EECBS gets under kAuto before LaCAM takes the rest, in (0, 1].
  double eecbs_budget_fraction = 0.8;
  double eecbs_suboptimality = 1.2;  ///< w of EECBS, ≥ 1
  int lns_neighborhood_size = 8;     ///< agents replanned per refinement iteration, ≥ 2
  /// Return only plans without rotations (robots following each other around a cycle in one
  /// step), which an ActionDependencyGraph needs; refinement then never lets a replanned
  /// robot follow another.
  bool forbid_rotations = false;
  /// Two robots sent to one goal: kRefuse gives InvalidArgument; kWaitNearby lets the robot
  /// nearer the goal (by path length; the lower index on ties) have it and plans each other one
  /// to the nearest free vertex (breadth-first from the goal) that is nobody's goal — a
  /// waiting spot from which a later plan can bring it in once the goal is free.
  enum class DuplicateGoals { kRefuse, kWaitNearby };
  DuplicateGoals duplicate_goals = DuplicateGoals::kWaitNearby;

  absl::Status Validate() const;
};

/// `instance` with every goal that another agent also has replaced by a waiting spot, as
/// MapfPlannerParams::DuplicateGoals::kWaitNearby describes. Other instances come back as given.
MapfInstance ResolveDuplicateGoals(const MapfInstance& instance);

/// The multi-robot planner entry point: picks a solver for the instance and the budget and
/// returns the best plan found. First plan — kAuto and kLacam: LaCAM (LacamSolver, usually
/// milliseconds), handed to the observer at once; then, kAuto with at most `eecbs_max_agents`
/// agents, EECBS (EecbsSolver, bounded-suboptimal) within `eecbs_budget_fraction` of the
/// budget, the cheaper plan wins; kEecbs: EECBS alone. With `forbid_rotations` any rotation is
/// then replanned away (LnsRefiner::RemoveRotations). With `anytime` the rest of the budget
/// refines the plan by large neighbourhood search (LnsRefiner), which only ever lowers the sum
/// of costs. Robots sent to one goal are handled by `duplicate_goals`; the result's
/// `planned_goals` says where each robot was sent. Stateless between calls.
class MapfPlanner : public MapfSolver {
 public:
  explicit MapfPlanner(const MapfPlannerParams& params) : params_(params) {}

  std::string Name() const override { return "auto"; }
  /// EECBS's w under kEecbs without rotation repair (which may lengthen paths); 0 otherwise.
  double SuboptimalityBound() const override;
  absl::StatusOr<MapfResult> Solve(const MapfInstance& instance, const MapfStopCondition& stop,
                                   const MapfPlanObserver& on_plan = nullptr) override;

  /// Replans from the robots' current positions (instance.starts) while each robot keeps its
  /// committed prefix: committed[i][0] is robot i's current vertex and the following entries
  /// are the moves it has already started or promised, which the returned paths begin with.
  /// Prioritized planning with SIPP in the revised form of Čáp et al. ("Prioritized Planning
  /// Algorithms for Trajectory Coordination of Multiple Mobile Robots", IEEE T-ASE 2015: robots
  /// not yet planned are obstacles where their prefixes end) alternated with the plain form,
  /// restarted with random orders for half the budget. If no order works and the prefixes,
  /// padded with waits to one length, still fit together, Solve plans all robots from where
  /// they end (complete, unlike prioritized planning) and the prefixes are put in front. Then
  /// rotation repair and LNS refinement as in Solve, never touching a prefix. Errors:
  /// InvalidArgument (bad instance or prefixes: wrong count, not starting at the start, not a
  /// move, two prefixes meeting — named), DeadlineExceeded (no plan within the budget),
  /// Cancelled.
  absl::StatusOr<MapfResult> Replan(const MapfInstance& instance,
                                    const std::vector<std::vector<int>>& committed,
                                    const MapfStopCondition& stop);

 private:
  // What Solve and Replan check first: the parameters, the stop condition and the instance with
  // its duplicate goals resolved (as duplicate_goals says).
  absl::StatusOr<MapfInstance> Prepare(const MapfInstance& requested,
                                       const MapfStopCondition& stop) const;
  // The steps Solve and Replan share: rotations out (with forbid_rotations), then LNS
  // refinement with the budget `watch` has left; fixed_steps as LnsRefiner takes them. Hands
  // each changed plan to `on_plan`.
  absl::Status RepairAndRefine(const MapfInstance& instance, const std::vector<int>& fixed_steps,
                               const MapfStopwatch& watch, const MapfPlanObserver& on_plan,
                               MapfResult* result);

  MapfPlannerParams params_;
};

}  // namespace fleetnav::planner
