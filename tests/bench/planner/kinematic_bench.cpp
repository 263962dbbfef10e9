// Heterogeneous multi-robot planning figures: PlanKinematicMapf on seeded mixed fleets (three
// forward-only robots, three omni and two 2 x 2 platforms) on random-32-32-10 from
// --data_dir. Counter: the plan's makespan in steps.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <iostream>
#include <string>

#include "bench_registry.hpp"
#include "fleetnav/planner/kinematic/kinematic_mapf.hpp"
#include "kinematic_fleet.hpp"

namespace fp = fleetnav::planner;

namespace {

void RunKinematicMixedFleet(benchmark::State& state, const fp::MovingAiMap& map) {
  const fp::KinematicMapfProblem problem =
      fp::testing::RandomMixedFleet(map, static_cast<uint64_t>(state.range(0)));
  size_t makespan = 0;
  for (auto _ : state) {
    fp::KinematicMapfParams params;
    params.time_limit_s = 10.0;
    absl::StatusOr<fp::KinematicMapfPlan> plan = fp::PlanKinematicMapf(problem, params);
    if (!plan.ok()) {
      state.SkipWithError(std::string(plan.status().message()).c_str());
      break;
    }
    makespan = 0;
    for (const auto& states : plan->states) makespan = std::max(makespan, states.size() - 1);
  }
  state.counters["makespan"] = static_cast<double>(makespan);
}

}  // namespace

namespace fleetnav::planner::bench {

void RegisterKinematicBenchmarks(const std::string& data_dir) {
  absl::StatusOr<fp::MovingAiMap> map = fp::LoadMovingAiMap(data_dir + "/random-32-32-10.map");
  if (!map.ok()) {
    std::cerr << "planner_bench: " << map.status() << " (--data_dir=" << data_dir << ")\n";
    std::exit(2);
  }
  benchmark::RegisterBenchmark("BM_KinematicMixedFleet", RunKinematicMixedFleet, *map)
      ->DenseRange(1, 10)
      ->Unit(benchmark::kMillisecond);
}

}  // namespace fleetnav::planner::bench
