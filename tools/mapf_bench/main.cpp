// fleetnav-mapf-bench: wiring only. Loads a MovingAI map and a scenario (or draws a seeded
// random instance), runs the multi-robot planner, validates the plan and prints one JSON object.
#include <CLI/CLI.hpp>
#include <chrono>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/version.hpp"
#include "fleetnav/planner/grid/movingai.hpp"
#include "fleetnav/planner/mapf/mapf.hpp"
#include "fleetnav/planner/mapf/mapf_planner.hpp"

namespace fp = fleetnav::planner;

int main(int argc, char** argv) {
  CLI::App app{"fleetnav-mapf-bench: multi-robot path finding on MovingAI benchmarks"};
  app.set_version_flag("--version", std::string(fleetnav::Version()));
  std::string map_path, scen_path, paths_out, solver = "auto";
  std::optional<uint64_t> seed;
  int agents = 0;
  double time_limit_s = 1.0;
  bool json = false;
  app.add_option("--map", map_path, "MovingAI .map file")->required();
  auto* scen = app.add_option("--scen", scen_path, "MovingAI .scen file");
  auto* seed_opt = app.add_option("--seed", seed, "draw a random instance with this seed");
  scen->excludes(seed_opt);
  app.add_option("--agents", agents, "number of agents")->required()->check(CLI::PositiveNumber);
  app.add_option("--time-limit-s", time_limit_s, "planning budget")->capture_default_str();
  app.add_option("--paths-out", paths_out, "write the paths, one line per agent");
  app.add_option("--solver", solver, "auto, lacam or eecbs")->capture_default_str();
  double w = 1.2;
  app.add_option("--w", w, "EECBS suboptimality bound")->capture_default_str();
  int neighborhood = 8;
  app.add_option("--lns-neighborhood", neighborhood, "agents replanned per LNS iteration")
      ->capture_default_str()
      ->check(CLI::Range(2, 1000));
  bool no_refine = false;
  app.add_flag("--no-refine", no_refine, "return the first plan, no LNS refinement");
  app.add_flag("--json", json, "print one JSON object (the only output format)");
  CLI11_PARSE(app, argc, argv);
  if (scen_path.empty() && !seed) {
    std::cerr << "one of --scen or --seed is required\n";
    return 2;
  }

  nlohmann::json out;
  auto fail = [&](const absl::Status& status) {
    out["solved"] = false;
    out["error"] = std::string(status.ToString());
    std::cout << out.dump() << "\n";
    return 1;
  };
  absl::StatusOr<fp::MovingAiMap> map = fp::LoadMovingAiMap(map_path);
  if (!map.ok()) return fail(map.status());
  const fp::GridGraph graph(*map);
  absl::StatusOr<fp::MapfInstance> instance;
  if (seed) {
    instance = fp::RandomInstance(graph, agents, *seed);
  } else {
    absl::StatusOr<std::vector<fp::ScenarioEntry>> entries = fp::LoadMovingAiScenario(scen_path);
    if (!entries.ok()) return fail(entries.status());
    instance = fp::InstanceFromScenario(graph, *entries, agents);
  }
  if (!instance.ok()) return fail(instance.status());

  fp::MapfPlannerParams params;
  params.seed = seed.value_or(0);
  params.eecbs_suboptimality = w;
  params.lns_neighborhood_size = neighborhood;
  params.anytime = !no_refine;
  if (solver == "lacam") {
    params.selection = fp::MapfPlannerParams::Selection::kLacam;
  } else if (solver == "eecbs") {
    params.selection = fp::MapfPlannerParams::Selection::kEecbs;
  } else if (solver != "auto") {
    return fail(absl::InvalidArgumentError("--solver: auto, lacam or eecbs"));
  }
  fp::MapfPlanner planner(params);
  const int64_t lower_bound = fp::SumOfCostsLowerBound(*instance);
  // The observer times when the caller holds the first plan, and keeps every improvement for
  // the anytime curve.
  using Clock = std::chrono::steady_clock;
  const Clock::time_point started = Clock::now();
  std::optional<double> first_plan_delivered_ms;
  std::vector<std::pair<double, int64_t>> improvements;  // (ms since Solve began, sum of costs)
  const fp::MapfPlanObserver observe = [&](const fp::MapfResult& plan) {
    const double at_ms = std::chrono::duration<double, std::milli>(Clock::now() - started).count();
    if (!first_plan_delivered_ms) first_plan_delivered_ms = at_ms;
    improvements.emplace_back(at_ms, fp::SumOfCosts(*instance, plan.solution));
  };
  absl::StatusOr<fp::MapfResult> result =
      planner.Solve(*instance, fp::MapfStopCondition{time_limit_s}, observe);
  out["agents"] = agents;
  out["soc_lower_bound"] = lower_bound;
  if (!result.ok()) return fail(result.status());
  if (absl::Status valid = fp::ValidateSolution(*instance, result->solution); !valid.ok()) {
    return fail(absl::InternalError(std::string(valid.message())));
  }
  const int64_t soc = fp::SumOfCosts(*instance, result->solution);
  out["solved"] = true;
  out["solver"] = result->solver;
  out["first_solution_ms"] = result->first_solution_ms;
  out["first_plan_delivered_ms"] = first_plan_delivered_ms.value_or(-1.0);
  // soc / lower bound of the best plan held after each checkpoint within the budget.
  nlohmann::json curve = nlohmann::json::object();
  for (const double checkpoint_s : {0.1, 1.0, 10.0, 100.0}) {
    if (checkpoint_s > time_limit_s) break;
    int64_t held = -1;
    for (const auto& [at_ms, cost] : improvements) {
      if (at_ms <= checkpoint_s * 1e3) held = cost;
    }
    if (held >= 0 && lower_bound > 0) {
      curve[absl::StrCat(checkpoint_s)] = static_cast<double>(held) / lower_bound;
    }
  }
  out["soc_over_lb_at_s"] = curve;
  out["final_ms"] = result->final_ms;
  out["soc"] = soc;
  out["soc_over_lb"] = lower_bound > 0 ? static_cast<double>(soc) / lower_bound : 1.0;
  out["makespan"] = fp::Makespan(*instance, result->solution);
  out["proven_optimal"] = result->proven_optimal;
  out["refine_iterations"] = result->refine_iterations;
  out["refine_accepted"] = result->refine_accepted;
  if (!paths_out.empty()) {
    std::ofstream file(paths_out);
    file << fp::FormatPaths(graph, result->solution);
    if (!file) return fail(absl::UnavailableError("--paths-out: cannot write " + paths_out));
  }
  std::cout << out.dump() << "\n";
  return 0;
}
