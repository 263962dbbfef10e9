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
  const bool try_eecbs = params_.selection == MapfPlannerParams::Selection::kEecbs ||
                         (params_.selection == MapfPlannerParams::Selection::kAuto &&
                          instance.num_agents() <= params_.eecbs_max_agents);
  if (try_eecbs) {
    EecbsParams eecbs;
    eecbs.suboptimality = params_.eecbs_suboptimality;
    eecbs.time_limit_s = params_.selection == MapfPlannerParams::Selection::kEecbs
                             ? params_.time_limit_s
                             : params_.time_limit_s * params_.eecbs_budget_fraction;
    absl::StatusOr<MapfResult> r = EecbsSolver(instance, eecbs).Solve(stop);
    if (r.ok() || params_.selection == MapfPlannerParams::Selection::kEecbs) return r;
    if (r.status().code() == absl::StatusCode::kCancelled) return r;
  }
  const double spent_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  LacamParams lacam;
  lacam.time_limit_s = std::max(params_.time_limit_s - spent_ms / 1000.0, 1e-3);
  lacam.seed = params_.seed;
  lacam.anytime = params_.anytime;
  absl::StatusOr<MapfResult> r = LacamSolver(instance, lacam).Solve(stop);
  if (r.ok()) {
    r->first_solution_ms += spent_ms;
    r->final_ms += spent_ms;
  }
  return r;
}

}  // namespace fleetnav::planner
