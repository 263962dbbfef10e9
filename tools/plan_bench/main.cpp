// fleetnav-plan-bench: wiring only. Builds one costmap per robot model on a generated or
// MovingAI map, runs every single-robot planner through one ompl::tools::Benchmark, writes
// OMPL's benchmark log and prints a JSON summary.
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/tools/benchmark/Benchmark.h>
#include <ompl/util/Console.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bench_map.hpp"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/version.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"
#include "ompl_benchmark_adapter.hpp"

namespace fp = fleetnav::planner;
namespace ob = ompl::base;

namespace {

struct Entry {
  std::string name;
  fleetnav::RobotModel model;
  fp::PlannerKind kind;
};

std::vector<Entry> AllPlanners() {
  return {
      {"lattice-lely", fleetnav::LelyVectorModel(), fp::PlannerKind::kLattice},
      {"lattice-omni", fleetnav::MecanumPlatformModel(), fp::PlannerKind::kLattice},
      {"lattice-ackermann", fleetnav::AckermannDeliveryModel(), fp::PlannerKind::kLattice},
      {"ompl-omni", fleetnav::MecanumPlatformModel(), fp::PlannerKind::kOmplOmni},
      {"ompl-reeds-shepp", fleetnav::AckermannDeliveryModel(), fp::PlannerKind::kOmplReedsShepp}};
}

std::optional<fleetnav::Pose2> ParsePose(const std::string& text) {
  std::stringstream in(text);
  double x, y, yaw;
  char c1, c2;
  if (!(in >> x >> c1 >> y >> c2 >> yaw) || c1 != ',' || c2 != ',') return std::nullopt;
  return fleetnav::Pose2(x, y, yaw);
}

double Median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fleetnav-plan-bench: single-robot planners under ompl::tools::Benchmark"};
  app.set_version_flag("--version", std::string(fleetnav::Version()));
  std::string map_path, start_text = "4,4,0", goal_text = "78,69,0", log_out, planners_text;
  double resolution_m = 0.5, padding_m = 0.15, time_limit_s = 5.0;
  unsigned runs = 10;
  uint64_t map_seed = 7;
  uint32_t seed = 1;
  bool json = false;
  app.add_option("--map", map_path, "MovingAI .map file (default: the generated 200k-cell map)");
  app.add_option("--resolution-m", resolution_m, "cell size of a MovingAI map")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--map-seed", map_seed, "seed of the generated map's boxes")
      ->capture_default_str();
  app.add_option("--start", start_text, "start pose x,y,yaw (m, m, rad)")->capture_default_str();
  app.add_option("--goal", goal_text, "goal pose x,y,yaw (m, m, rad)")->capture_default_str();
  app.add_option("--padding-m", padding_m, "costmap padding around each footprint")
      ->capture_default_str();
  app.add_option("--runs", runs, "runs per planner")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--time-limit-s", time_limit_s, "budget per run")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "seed of the OMPL planners' first run (run k uses seed + k)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--planners", planners_text,
                 "comma-separated subset of lattice-lely, lattice-omni, lattice-ackermann, "
                 "ompl-omni, ompl-reeds-shepp (default: all)");
  app.add_option("--log-out", log_out, "write OMPL's benchmark log (ompl_benchmark_statistics.py)");
  app.add_flag("--json", json, "print a JSON summary per planner");
  CLI11_PARSE(app, argc, argv);
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);

  auto fail = [](const std::string& what) {
    std::cerr << "fleetnav-plan-bench: " << what << "\n";
    return 1;
  };
  const std::optional<fleetnav::Pose2> start = ParsePose(start_text);
  const std::optional<fleetnav::Pose2> goal = ParsePose(goal_text);
  if (!start || !goal) return fail("--start/--goal: expected x,y,yaw");
  absl::StatusOr<fleetnav::OccupancyGrid> grid =
      map_path.empty()
          ? absl::StatusOr<fleetnav::OccupancyGrid>(fleetnav::plan_bench::GeneratedMap(map_seed))
          : fleetnav::plan_bench::MovingAiGrid(map_path, resolution_m);
  if (!grid.ok()) return fail(std::string(grid.status().ToString()));

  std::vector<Entry> entries;
  for (Entry& e : AllPlanners()) {
    if (planners_text.empty() ||
        ("," + planners_text + ",").find("," + e.name + ",") != std::string::npos) {
      entries.push_back(std::move(e));
    }
  }
  if (entries.empty()) return fail("--planners: no known planner named");

  // One costmap per robot kind, built once (as per site map); planning alone is timed.
  fp::CostmapParams cp;
  cp.padding_m = padding_m;
  std::map<std::string, std::unique_ptr<fp::Costmap>> costmaps;
  for (const Entry& e : entries) {
    if (costmaps.count(e.model.kind_name) > 0) continue;
    absl::StatusOr<fp::Costmap> c = fp::Costmap::Build(*grid, e.model.footprint_m, cp);
    if (!c.ok()) return fail(std::string(c.status().ToString()));
    costmaps[e.model.kind_name] = std::make_unique<fp::Costmap>(*std::move(c));
  }
  fp::Costmap* reference = costmaps.begin()->second.get();

  // The benchmark's own problem: SE2 over the map; its validity (used only for OMPL's
  // "correct solution" property) tests the reference point, each planner its own footprint.
  auto space = std::make_shared<ob::SE2StateSpace>();
  ob::RealVectorBounds bounds(2);
  bounds.setLow(0.0);
  bounds.setHigh(0, reference->width() * reference->resolution_m());
  bounds.setHigh(1, reference->height() * reference->resolution_m());
  space->setBounds(bounds);
  ompl::geometric::SimpleSetup setup(space);
  setup.setStateValidityChecker([reference](const ob::State* s) {
    const auto* st = s->as<ob::SE2StateSpace::StateType>();
    const double res = reference->resolution_m();
    const int x = static_cast<int>(std::floor(st->getX() / res));
    const int y = static_cast<int>(std::floor(st->getY() / res));
    return reference->InBounds(x, y) && !reference->IsObstacle(x, y);
  });
  ob::ScopedState<ob::SE2StateSpace> s(space), g(space);
  s->setXY(start->x_m(), start->y_m());
  s->setYaw(start->yaw_rad() >= fleetnav::kPi ? start->yaw_rad() - 2 * fleetnav::kPi
                                              : start->yaw_rad());
  g->setXY(goal->x_m(), goal->y_m());
  g->setYaw(goal->yaw_rad() >= fleetnav::kPi ? goal->yaw_rad() - 2 * fleetnav::kPi
                                             : goal->yaw_rad());
  fp::PathRequest request;
  request.start = *start;
  request.goal = *goal;
  request.time_limit_s = time_limit_s;
  setup.setStartAndGoalStates(s, g, request.goal_tolerance_m);
  setup.setup();

  ompl::tools::Benchmark bench(setup, "fleetnav single-robot planners");
  std::map<std::string, std::shared_ptr<fp::SingleRobotPlannerAdapter>> adapters;
  for (const Entry& e : entries) {
    fp::Costmap* costmap = costmaps[e.model.kind_name].get();
    fp::SingleRobotPlannerParams params;
    params.kind = e.kind;
    auto adapter = std::make_shared<fp::SingleRobotPlannerAdapter>(
        setup.getSpaceInformation(), e.name,
        [costmap, model = e.model, params, seed](int run) {
          fp::SingleRobotPlannerParams p = params;
          p.ompl.seed = seed + static_cast<uint32_t>(run);
          return fp::MakeSingleRobotPlanner(costmap, model, p);
        },
        request);
    adapters["geometric_" + e.name] = adapter;
    bench.addPlanner(adapter);
  }
  bench.setPostRunEvent(
      [](const ob::PlannerPtr& planner, ompl::tools::Benchmark::RunProperties& run) {
        const auto* adapter = dynamic_cast<const fp::SingleRobotPlannerAdapter*>(planner.get());
        const bool ok = adapter != nullptr && adapter->last_result().ok();
        run["exact BOOLEAN"] = ok && adapter->last_result()->exact ? "1" : "0";
        if (ok) {
          run["path length_m REAL"] = std::to_string(adapter->last_result()->length_m);
          run["expanded INTEGER"] = std::to_string(adapter->last_result()->expanded);
        }
      });
  ompl::tools::Benchmark::Request req(time_limit_s, 4096.0, runs, 0.05,
                                      /*displayProgress=*/false, /*saveConsoleOutput=*/false,
                                      /*simplify=*/false);
  bench.benchmark(req);
  if (!log_out.empty() && !bench.saveResultsToFile(log_out.c_str())) {
    return fail("--log-out: cannot write " + log_out);
  }

  nlohmann::json out;
  out["map"] = map_path.empty() ? "generated" : map_path;
  out["cells"] = static_cast<int64_t>(grid->width()) * grid->height();
  out["resolution_m"] = grid->resolution_m();
  out["start"] = {start->x_m(), start->y_m(), start->yaw_rad()};
  out["goal"] = {goal->x_m(), goal->y_m(), goal->yaw_rad()};
  out["straight_line_m"] = (goal->translation() - start->translation()).norm();
  out["runs"] = runs;
  out["time_limit_s"] = time_limit_s;
  out["planners"] = nlohmann::json::array();
  for (const auto& p : bench.getRecordedExperimentData().planners) {
    std::vector<double> times_ms, lengths_m;
    int exact = 0, approximate = 0;
    for (const auto& run : p.runs) {
      auto get = [&run](const std::string& key) {
        const auto it = run.find(key);
        return it == run.end() ? std::string() : it->second;
      };
      if (!get("time REAL").empty()) times_ms.push_back(1e3 * std::stod(get("time REAL")));
      if (get("exact BOOLEAN") == "1") {
        ++exact;
        lengths_m.push_back(std::stod(get("path length_m REAL")));
      } else if (get("approximate solution BOOLEAN") == "1") {
        ++approximate;
      }
    }
    const double n = std::max<size_t>(1, p.runs.size());
    out["planners"].push_back({{"name", p.name},
                               {"solved_rate", exact / n},
                               {"approximate_rate", approximate / n},
                               {"median_time_ms", Median(times_ms)},
                               {"median_length_m", Median(lengths_m)}});
    const auto adapter = adapters.find(p.name);
    if (adapter != adapters.end() && !adapter->second->last_result().ok()) {
      out["planners"].back()["last_error"] =
          std::string(adapter->second->last_result().status().ToString());
    }
  }
  if (json) {
    std::cout << out.dump() << "\n";
  } else {
    for (const auto& p : out["planners"]) {
      std::cout << p["name"].get<std::string>() << ": solved " << p["solved_rate"] << ", median "
                << p["median_time_ms"] << " ms, " << p["median_length_m"] << " m\n";
    }
  }
  return 0;
}
