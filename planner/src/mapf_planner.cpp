#include "fleetnav/planner/mapf_planner.hpp"

#include <chrono>
#include <cmath>

#include "fleetnav/planner/eecbs.hpp"
#include "fleetnav/planner/lacam.hpp"
#include "fleetnav/planner/lns.hpp"

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
  if (!(time_limit_s > 0.0) || !std::isfinite(time_limit_s)) {
    return absl::InvalidArgumentError("time_limit_s: must be finite and > 0");
  }
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

absl::StatusOr<MapfResult> MapfPlanner::Solve(const MapfInstance& requested, std::stop_token stop) {
  if (absl::Status s = params_.Validate(); !s.ok()) return s;
  const MapfInstance instance =
      params_.duplicate_goals == MapfPlannerParams::DuplicateGoals::kWaitNearby
          ? ResolveDuplicateGoals(requested)
          : requested;
  if (absl::Status s = instance.Validate(); !s.ok()) return s;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  auto spent_s = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  auto remaining_s = [&] { return std::max(params_.time_limit_s - spent_s(), 1e-3); };
  using Selection = MapfPlannerParams::Selection;

  auto run_eecbs = [&](double budget_s) {
    EecbsParams eecbs;
    eecbs.suboptimality = params_.eecbs_suboptimality;
    eecbs.time_limit_s = budget_s;
    return EecbsSolver(instance, eecbs).Solve(stop);
  };
  auto run_lacam = [&] {
    LacamParams lacam;
    lacam.time_limit_s = remaining_s();
    lacam.seed = params_.seed;
    lacam.anytime = false;
    return LacamSolver(instance, lacam).Solve(stop);
  };

  // 1. A first plan: EECBS alone, LaCAM alone, or (kAuto with few agents) a quick LaCAM plan
  //    as the fallback and then EECBS within its share of the budget; the cheaper one wins.
  absl::StatusOr<MapfResult> best;
  const bool few = instance.num_agents() <= params_.eecbs_max_agents;
  if (params_.selection == Selection::kEecbs) {
    best = run_eecbs(params_.time_limit_s);
  } else {
    best = run_lacam();
    if (best.ok() && params_.selection == Selection::kAuto && few) {
      const double first_ms = best->first_solution_ms;
      const double eecbs_budget_s =
          std::max(params_.time_limit_s * params_.eecbs_budget_fraction - spent_s(), 1e-3);
      absl::StatusOr<MapfResult> e = run_eecbs(eecbs_budget_s);
      if (e.ok() && SumOfCosts(instance, e->solution) <= SumOfCosts(instance, best->solution)) {
        e->first_solution_ms = first_ms;
        e->final_ms = spent_s() * 1000.0;
        best = std::move(e);
      }
    }
  }
  if (!best.ok()) return best;
  best->planned_goals = instance.goals;

  // 2. and 3. Rotations out, then refinement while the budget lasts.
  if (absl::Status st = RepairAndRefine(instance, {}, t0, stop, &*best); !st.ok()) return st;
  return best;
}

absl::Status MapfPlanner::RepairAndRefine(const MapfInstance& instance,
                                          const std::vector<int>& fixed_steps,
                                          std::chrono::steady_clock::time_point started,
                                          std::stop_token stop, MapfResult* result) {
  using Clock = std::chrono::steady_clock;
  auto spent_s = [&] { return std::chrono::duration<double>(Clock::now() - started).count(); };
  LnsParams lns;
  lns.seed = params_.seed;
  lns.neighborhood_size = params_.lns_neighborhood_size;
  lns.forbid_following = params_.forbid_rotations;
  int step = 0;
  if (params_.forbid_rotations && !FindRotation(result->solution, &step).empty()) {
    // Rotation removal may overrun a spent budget a little: a plan the robots cannot execute
    // is worth nothing.
    lns.time_limit_s = std::max(params_.time_limit_s - spent_s(), 0.1);
    absl::StatusOr<MapfSolution> repaired =
        LnsRefiner(instance, lns).RemoveRotations(result->solution, stop, fixed_steps);
    if (!repaired.ok()) return repaired.status();
    result->solution = *std::move(repaired);
    result->final_ms = spent_s() * 1000.0;
    result->solver += "+rotation-repair";
  }
  if (params_.anytime && spent_s() < params_.time_limit_s && !stop.stop_requested()) {
    lns.time_limit_s = params_.time_limit_s - spent_s();
    const double offset_ms = spent_s() * 1000.0;
    LnsStats stats;
    absl::StatusOr<MapfSolution> refined =
        LnsRefiner(instance, lns).Refine(result->solution, stop, fixed_steps, &stats);
    result->refine_iterations = stats.iterations;
    result->refine_accepted = stats.accepted;
    if (refined.ok() && stats.accepted > 0) {
      result->solution = *std::move(refined);
      result->final_ms = offset_ms + stats.last_improvement_ms;
      result->solver += "+lns";
    }
  }
  return absl::OkStatus();
}

}  // namespace fleetnav::planner
