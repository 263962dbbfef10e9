#include "fleetnav/planner/mapf/mapf_planner.hpp"

#include <algorithm>
#include <cmath>

#include "fleetnav/planner/mapf/eecbs.hpp"
#include "fleetnav/planner/mapf/lacam.hpp"
#include "fleetnav/planner/mapf/lns.hpp"

namespace fleetnav::planner {

MapfInstance ResolveDuplicateGoals(const MapfInstance& instance) {
  MapfInstance out = instance;
  const GridGraph& g = *instance.graph;
  const int n = instance.num_agents();
  if (g.size() == 0) return out;
  std::vector<int> owner(g.size(), -1);  // the agent keeping each goal vertex
  for (int i = 0; i < n; ++i) {
    const int goal = instance.goals[i];
    if (goal < 0 || goal >= g.size() || instance.starts[i] < 0 || instance.starts[i] >= g.size())
      continue;  // Validate names it
    const int keeper = owner[goal];
    if (keeper < 0) {
      owner[goal] = i;
      continue;
    }
    DistanceTable dist(g, goal);
    if (dist.Get(instance.starts[i]) < dist.Get(instance.starts[keeper])) owner[goal] = i;
  }
  for (int i = 0; i < n; ++i) {
    const int goal = instance.goals[i];
    if (goal < 0 || goal >= g.size() || owner[goal] == i) continue;
    // Breadth-first from the goal: among the nearest vertices nobody ends on, the one nearest
    // to the robot (so it need not pass the robot that keeps the goal).
    std::vector<int> depth(g.size(), -1);
    std::vector<int> queue = {goal};
    depth[goal] = 0;
    int found_depth = -1, best = -1, best_from_start = 0;
    DistanceTable from_start(g, instance.starts[i]);
    for (size_t head = 0; head < queue.size(); ++head) {
      const int v = queue[head];
      if (found_depth >= 0 && depth[v] > found_depth) break;
      if (owner[v] < 0) {
        found_depth = depth[v];
        const int d = from_start.Get(v);
        if (best < 0 || d < best_from_start) {
          best = v;
          best_from_start = d;
        }
      }
      for (int k = 0; k < g.Degree(v); ++k) {
        const int u = g.Neighbor(v, k);
        if (depth[u] < 0) {
          depth[u] = depth[v] + 1;
          queue.push_back(u);
        }
      }
    }
    if (best >= 0) {
      owner[best] = i;
      out.goals[i] = best;
    }
  }
  return out;
}

absl::Status MapfPlannerParams::Validate() const {
  if (eecbs_max_agents < 0) return absl::InvalidArgumentError("eecbs_max_agents: must be >= 0");
  if (!(eecbs_budget_fraction > 0.0 && eecbs_budget_fraction <= 1.0)) {
    return absl::InvalidArgumentError("eecbs_budget_fraction: must be in (0, 1]");
  }
  if (!(eecbs_suboptimality >= 1.0) || !std::isfinite(eecbs_suboptimality)) {
    return absl::InvalidArgumentError("eecbs_suboptimality: must be finite and >= 1");
  }
  if (lns_neighborhood_size < 2) {
    return absl::InvalidArgumentError("lns_neighborhood_size: must be >= 2");
  }
  return absl::OkStatus();
}

double MapfPlanner::SuboptimalityBound() const {
  return params_.selection == MapfPlannerParams::Selection::kEecbs && !params_.forbid_rotations
             ? params_.eecbs_suboptimality
             : 0.0;
}

absl::StatusOr<MapfInstance> MapfPlanner::Prepare(const MapfInstance& requested,
                                                  const MapfStopCondition& stop) const {
  if (absl::Status s = params_.Validate(); !s.ok()) return s;
  if (absl::Status s = stop.Validate(); !s.ok()) return s;
  const MapfInstance instance =
      params_.duplicate_goals == MapfPlannerParams::DuplicateGoals::kWaitNearby
          ? ResolveDuplicateGoals(requested)
          : requested;
  if (absl::Status s = instance.Validate(); !s.ok()) return s;
  return instance;
}

absl::StatusOr<MapfResult> MapfPlanner::Solve(const MapfInstance& requested,
                                              const MapfStopCondition& stop,
                                              const MapfPlanObserver& on_plan) {
  absl::StatusOr<MapfInstance> prepared = Prepare(requested, stop);
  if (!prepared.ok()) return prepared.status();
  const MapfInstance& instance = *prepared;
  const MapfStopwatch watch(stop);
  using Selection = MapfPlannerParams::Selection;
  EecbsParams eecbs;
  eecbs.suboptimality = params_.eecbs_suboptimality;
  LacamParams lacam;
  lacam.seed = params_.seed;
  lacam.anytime = false;
  // The observer sees each plan in the requested robots' goals (planned_goals says where a
  // robot sent to a taken goal goes instead).
  // With forbid_rotations a plan is handed over only once it is free of rotations.
  auto hand_over = [&](const MapfResult& plan) {
    int step = 0;
    if (!on_plan || (params_.forbid_rotations && !FindRotation(plan.solution, &step).empty())) {
      return;
    }
    MapfResult copy = plan;
    copy.planned_goals = instance.goals;
    on_plan(copy);
  };

  // 1. A first plan: EECBS alone, or LaCAM (handed over at once) and then, with few agents
  //    under kAuto, EECBS within its share of the budget; the cheaper one wins.
  absl::StatusOr<MapfResult> best;
  const bool few = instance.num_agents() <= params_.eecbs_max_agents;
  if (params_.selection == Selection::kEecbs) {
    best = EecbsSolver(eecbs).Solve(instance, stop);
    if (best.ok()) hand_over(*best);
  } else {
    best = LacamSolver(lacam).Solve(instance, watch.Remaining());
    if (best.ok()) hand_over(*best);
    if (best.ok() && params_.selection == Selection::kAuto && few && !watch.StopRequested()) {
      const double first_ms = best->first_solution_ms;
      const MapfStopCondition share{
          std::max(stop.time_limit_s * params_.eecbs_budget_fraction - watch.ElapsedMs() * 1e-3,
                   1e-3),
          stop.token};
      absl::StatusOr<MapfResult> e = EecbsSolver(eecbs).Solve(instance, share);
      if (e.ok() && SumOfCosts(instance, e->solution) <= SumOfCosts(instance, best->solution)) {
        const bool cheaper =
            SumOfCosts(instance, e->solution) < SumOfCosts(instance, best->solution);
        e->first_solution_ms = first_ms;
        e->final_ms = watch.ElapsedMs();
        best = std::move(e);
        if (cheaper) hand_over(*best);
      }
    }
  }
  if (!best.ok()) return best;
  best->planned_goals = instance.goals;

  // 2. and 3. Rotations out, then refinement while the budget lasts.
  if (absl::Status st = RepairAndRefine(instance, {}, watch, on_plan, &*best); !st.ok()) return st;
  return best;
}

absl::Status MapfPlanner::RepairAndRefine(const MapfInstance& instance,
                                          const std::vector<int>& fixed_steps,
                                          const MapfStopwatch& watch,
                                          const MapfPlanObserver& on_plan, MapfResult* result) {
  const std::stop_token stop = watch.condition().token;
  LnsParams lns;
  lns.seed = params_.seed;
  lns.neighborhood_size = params_.lns_neighborhood_size;
  lns.forbid_following = params_.forbid_rotations;
  int step = 0;
  if (params_.forbid_rotations && !FindRotation(result->solution, &step).empty()) {
    // Rotation removal may overrun a spent budget a little: a plan the robots cannot execute
    // is worth nothing.
    lns.time_limit_s = watch.RemainingS(0.1);
    absl::StatusOr<MapfSolution> repaired =
        LnsRefiner(instance, lns).RemoveRotations(result->solution, stop, fixed_steps);
    if (!repaired.ok()) return repaired.status();
    result->solution = *std::move(repaired);
    result->final_ms = watch.ElapsedMs();
    result->solver += "+rotation-repair";
    if (on_plan) on_plan(*result);
  }
  if (params_.anytime && !watch.ShouldStop()) {
    lns.time_limit_s = watch.RemainingS(1e-3);
    const double offset_ms = watch.ElapsedMs();
    LnsStats stats;
    const std::string solver = result->solver + "+lns";
    LnsRefiner::ImprovementObserver on_improved = nullptr;
    if (on_plan) {
      on_improved = [&](const MapfSolution& improved, double elapsed_ms) {
        MapfResult copy = *result;
        copy.solution = improved;
        copy.final_ms = offset_ms + elapsed_ms;
        copy.solver = solver;
        on_plan(copy);
      };
    }
    absl::StatusOr<MapfSolution> refined =
        LnsRefiner(instance, lns).Refine(result->solution, stop, fixed_steps, &stats, on_improved);
    result->refine_iterations = stats.iterations;
    result->refine_accepted = stats.accepted;
    if (refined.ok() && stats.accepted > 0) {
      result->solution = *std::move(refined);
      result->final_ms = offset_ms + stats.last_improvement_ms;
      result->solver = solver;
    }
  }
  return absl::OkStatus();
}

}  // namespace fleetnav::planner
