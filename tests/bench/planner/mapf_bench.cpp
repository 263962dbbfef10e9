// Multi-robot planner figures: time to the first plan (LaCAM, not anytime) and to a
// bounded-suboptimal plan (EECBS) on the shared MovingAI maps. Counters report the sum of
// costs over the lower bound. Fails loudly when the data folder is missing.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <iostream>
#include <string>

#include "fleetnav/planner/eecbs.hpp"
#include "fleetnav/planner/lacam.hpp"
#include "fleetnav/planner/mapf.hpp"

namespace fp = fleetnav::planner;

namespace {

fp::MovingAiMap LoadOrDie(const std::string& name) {
  absl::StatusOr<fp::MovingAiMap> map =
      fp::LoadMovingAiMap(std::string(FLEETNAV_MAPF_DATA_DIR) + "/" + name);
  if (!map.ok()) {
    std::cerr << map.status() << "\n";
    std::abort();
  }
  return *map;
}

void RunLacam(benchmark::State& state, const char* map_name) {
  const fp::GridGraph graph(LoadOrDie(map_name));
  const int agents = static_cast<int>(state.range(0));
  const fp::MapfInstance inst = fp::RandomInstance(graph, agents, 1).value();
  const double lb = static_cast<double>(fp::SumOfCostsLowerBound(inst));
  double ratio = 0.0;
  for (auto _ : state) {
    fp::LacamParams params;
    params.time_limit_s = 10.0;
    params.anytime = false;
    absl::StatusOr<fp::MapfResult> r = fp::LacamSolver(inst, params).Solve();
    if (!r.ok()) {
      state.SkipWithError(std::string(r.status().message()).c_str());
      break;
    }
    ratio = static_cast<double>(fp::SumOfCosts(inst, r->solution)) / lb;
  }
  state.counters["soc_over_lb"] = ratio;
}

void BM_LacamRandom32(benchmark::State& state) { RunLacam(state, "random-32-32-20.map"); }
void BM_LacamWarehouse(benchmark::State& state) { RunLacam(state, "warehouse-20-40-10-2-2.map"); }
void BM_LacamDen520d(benchmark::State& state) { RunLacam(state, "den520d.map"); }

void BM_EecbsRandom32(benchmark::State& state) {
  const fp::GridGraph graph(LoadOrDie("random-32-32-20.map"));
  const fp::MapfInstance inst =
      fp::RandomInstance(graph, static_cast<int>(state.range(0)), 2).value();
  const double lb = static_cast<double>(fp::SumOfCostsLowerBound(inst));
  double ratio = 0.0;
  for (auto _ : state) {
    absl::StatusOr<fp::MapfResult> r = fp::EecbsSolver(inst, fp::EecbsParams{1.2, 10.0}).Solve();
    if (!r.ok()) {
      state.SkipWithError(std::string(r.status().message()).c_str());
      break;
    }
    ratio = static_cast<double>(fp::SumOfCosts(inst, r->solution)) / lb;
  }
  state.counters["soc_over_lb"] = ratio;
}

}  // namespace

BENCHMARK(BM_LacamRandom32)->Arg(100)->Arg(200)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LacamWarehouse)->Arg(1000)->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK(BM_LacamDen520d)->Arg(500)->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK(BM_EecbsRandom32)->Arg(50)->Arg(100)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
