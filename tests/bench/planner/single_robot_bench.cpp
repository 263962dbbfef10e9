// Single-robot planner figures: a long path on a 200k-cell map (500 × 400 cells at 0.2 m,
// seeded random boxes, 98.5 m straight), per planner. Counters: path length and expansions.
#include <benchmark/benchmark.h>
#include <ompl/util/Console.h>

#include <random>

#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"

namespace fp = fleetnav::planner;

namespace {

fleetnav::OccupancyGrid BigGrid() {
  fleetnav::OccupancyGrid grid =
      fleetnav::OccupancyGrid::Filled(500, 400, 0.2, fleetnav::Pose2(),
                                      fleetnav::OccupancyGrid::kFreeValue)
          .value();
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> x(20, 470), y(20, 370), size(3, 15);
  for (int k = 0; k < 80; ++k) {
    const int bx = x(rng), by = y(rng), sx = size(rng), sy = size(rng);
    for (int j = by; j < by + sy; ++j) {
      for (int i = bx; i < bx + sx; ++i)
        grid.SetValue({i, j}, fleetnav::OccupancyGrid::kOccupiedValue);
    }
  }
  for (int j = 0; j < 30; ++j) {
    for (int i = 0; i < 30; ++i) {
      grid.SetValue({i + 5, j + 5}, fleetnav::OccupancyGrid::kFreeValue);
      grid.SetValue({i + 375, j + 330}, fleetnav::OccupancyGrid::kFreeValue);
    }
  }
  return grid;
}

void Run(benchmark::State& state, fleetnav::RobotModel model,
         fp::PlannerKind kind = fp::PlannerKind::kLattice) {
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);  // OMPL informs on every solve
  fp::CostmapParams cp;
  cp.padding_m = 0.15;
  absl::StatusOr<fp::Costmap> costmap = fp::Costmap::Build(BigGrid(), model.footprint_m, cp);
  if (!costmap.ok()) {
    state.SkipWithError("costmap");
    return;
  }
  fp::PathRequest req;
  req.start = fleetnav::Pose2(4.0, 4.0, 0.0);
  req.goal = fleetnav::Pose2(78.0, 69.0, 0.0);  // 74 m straight-line, about 100 m of path
  req.time_limit_s = 10.0;
  double length = 0, expanded = 0;
  bool exact = false;
  for (auto _ : state) {
    // A fresh costmap cache each time would be unfair to a long-running planner; the costmap
    // is built once per site map, so only planning is timed.
    fp::SingleRobotPlannerParams params;
    params.kind = kind;
    absl::StatusOr<std::unique_ptr<fp::SingleRobotPlanner>> planner =
        fp::MakeSingleRobotPlanner(&*costmap, model, params);
    if (!planner.ok()) {
      state.SkipWithError(std::string(planner.status().message()).c_str());
      return;
    }
    absl::StatusOr<fp::PathResult> r = (*planner)->Plan(req);
    if (!r.ok()) {
      state.SkipWithError(std::string(r.status().message()).c_str());
      return;
    }
    length = r->length_m;
    expanded = static_cast<double>(r->expanded);
    exact = r->exact;
  }
  state.counters["length_m"] = length;
  state.counters["expanded"] = expanded;
  state.counters["exact"] = exact;
}

void BM_LatticeLely(benchmark::State& s) { Run(s, fleetnav::LelyVectorModel()); }
void BM_LatticeMecanum(benchmark::State& s) { Run(s, fleetnav::MecanumPlatformModel()); }
void BM_LatticeAckermann(benchmark::State& s) { Run(s, fleetnav::AckermannDeliveryModel()); }
// The OMPL planners plan with the same seed every iteration, so every iteration finds one path.
void BM_OmplOmni(benchmark::State& s) {
  Run(s, fleetnav::MecanumPlatformModel(), fp::PlannerKind::kOmplOmni);
}
void BM_OmplReedsShepp(benchmark::State& s) {
  Run(s, fleetnav::AckermannDeliveryModel(), fp::PlannerKind::kOmplReedsShepp);
}

}  // namespace

BENCHMARK(BM_LatticeLely)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LatticeMecanum)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LatticeAckermann)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OmplOmni)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OmplReedsShepp)->Unit(benchmark::kMillisecond);
