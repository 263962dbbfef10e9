// Heterogeneous multi-robot planning figures: PlanKinematicMapf on seeded mixed fleets (three
// forward-only robots, three omni and two 2 x 2 platforms) on random-32-32-10, the instances of
// the kinematic delay test. Counter: the plan's makespan in steps.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <iostream>
#include <string>

#include "fleetnav/planner/kinematic_mapf.hpp"
#include "kinematic_fleet.hpp"

namespace fp = fleetnav::planner;

namespace {

void BM_KinematicMixedFleet(benchmark::State& state) {
  absl::StatusOr<fp::MovingAiMap> map =
      fp::LoadMovingAiMap(std::string(FLEETNAV_MAPF_DATA_DIR) + "/random-32-32-10.map");
  if (!map.ok()) {
    std::cerr << map.status() << "\n";
    std::abort();
  }
  const fp::KinematicMapfProblem problem =
      fp::testing::RandomMixedFleet(*map, static_cast<uint64_t>(state.range(0)));
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

BENCHMARK(BM_KinematicMixedFleet)->DenseRange(1, 10)->Unit(benchmark::kMillisecond);
