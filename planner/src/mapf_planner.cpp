#include "fleetnav/planner/mapf_planner.hpp"

#include <chrono>
#include <cmath>

#include "fleetnav/planner/eecbs.hpp"
#include "fleetnav/planner/lacam.hpp"

namespace fleetnav::planner {

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
  return absl::OkStatus();
}

absl::StatusOr<MapfResult> MapfPlanner::Solve(const MapfInstance& instance, std::stop_token stop) {
  if (absl::Status s = params_.Validate(); !s.ok()) return s;
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
  auto run_lacam = [&](bool anytime) {
    LacamParams lacam;
    lacam.time_limit_s = remaining_s();
    lacam.seed = params_.seed;
    lacam.anytime = anytime;
    const double offset_ms = spent_s() * 1000.0;
    absl::StatusOr<MapfResult> r = LacamSolver(instance, lacam).Solve(stop);
    if (r.ok()) {
      r->first_solution_ms += offset_ms;
      r->final_ms += offset_ms;
    }
    return r;
  };
  if (params_.selection == Selection::kEecbs) return run_eecbs(params_.time_limit_s);
  if (params_.selection == Selection::kLacam || instance.num_agents() > params_.eecbs_max_agents) {
    return run_lacam(params_.anytime);
  }
  // Few agents: a quick LaCAM plan first (the fallback), then EECBS for a bounded-suboptimal
  // one within its share of the budget, then LaCAM* refinement with what is left.
  absl::StatusOr<MapfResult> best = run_lacam(/*anytime=*/false);
  if (!best.ok()) return best;
  const double first_ms = best->first_solution_ms;
  const double eecbs_budget_s =
      std::max(params_.time_limit_s * params_.eecbs_budget_fraction - spent_s(), 1e-3);
  absl::StatusOr<MapfResult> e = run_eecbs(eecbs_budget_s);
  if (e.ok() && SumOfCosts(instance, e->solution) <= SumOfCosts(instance, best->solution)) {
    e->first_solution_ms = first_ms;
    e->final_ms = spent_s() * 1000.0;
    return e;
  }
  if (params_.anytime && spent_s() < params_.time_limit_s && !stop.stop_requested()) {
    absl::StatusOr<MapfResult> refined = run_lacam(/*anytime=*/true);
    if (refined.ok() &&
        SumOfCosts(instance, refined->solution) < SumOfCosts(instance, best->solution)) {
      refined->first_solution_ms = first_ms;
      return refined;
    }
  }
  return best;
}

}  // namespace fleetnav::planner
