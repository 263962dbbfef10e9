// Multi-robot planner figures: time to the first plan (LaCAM, not anytime) and to a
// bounded-suboptimal plan (EECBS) on the MovingAI benchmark maps in the folder given
// by --data_dir. Counters report the sum of costs over the lower bound.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <iostream>
#include <string>

#include "bench_registry.hpp"
#include "fleetnav/planner/mapf/eecbs.hpp"
#include "fleetnav/planner/mapf/lacam.hpp"
#include "fleetnav/planner/mapf/mapf.hpp"

namespace fp = fleetnav::planner;

namespace {

fp::MovingAiMap LoadOrDie(const std::string& data_dir, const std::string& name) {
  absl::StatusOr<fp::MovingAiMap> map = fp::LoadMovingAiMap(data_dir + "/" + name);
  if (!map.ok()) {
    std::cerr << "planner_bench: " << map.status() << " (--data_dir=" << data_dir << ")\n";
    std::exit(2);
  }
  return *map;
}

void RunLacam(benchmark::State& state, const fp::MovingAiMap& map) {
  const fp::GridGraph graph(map);
  const int agents = static_cast<int>(state.range(0));
  const fp::MapfInstance inst = fp::RandomInstance(graph, agents, 1).value();
  const double lb = static_cast<double>(fp::SumOfCostsLowerBound(inst));
  double ratio = 0.0;
  for (auto _ : state) {
    fp::LacamParams params;
    params.anytime = false;
    absl::StatusOr<fp::MapfResult> r = fp::LacamSolver(params).Solve(inst, {10.0});
    if (!r.ok()) {
      state.SkipWithError(std::string(r.status().message()).c_str());
      break;
    }
    ratio = static_cast<double>(fp::SumOfCosts(inst, r->solution)) / lb;
  }
  state.counters["soc_over_lb"] = ratio;
}

void RunEecbs(benchmark::State& state, const fp::MovingAiMap& map) {
  const fp::GridGraph graph(map);
  const fp::MapfInstance inst =
      fp::RandomInstance(graph, static_cast<int>(state.range(0)), 2).value();
  const double lb = static_cast<double>(fp::SumOfCostsLowerBound(inst));
  double ratio = 0.0;
  for (auto _ : state) {
    absl::StatusOr<fp::MapfResult> r = fp::EecbsSolver(fp::EecbsParams{1.2}).Solve(inst, {10.0});
    if (!r.ok()) {
      state.SkipWithError(std::string(r.status().message()).c_str());
      break;
    }
    ratio = static_cast<double>(fp::SumOfCosts(inst, r->solution)) / lb;
  }
  state.counters["soc_over_lb"] = ratio;
}

}  // namespace

namespace fleetnav::planner::bench {

void RegisterMapfBenchmarks(const std::string& data_dir) {
  const fp::MovingAiMap random32 = LoadOrDie(data_dir, "random-32-32-20.map");
  const fp::MovingAiMap warehouse = LoadOrDie(data_dir, "warehouse-20-40-10-2-2.map");
  const fp::MovingAiMap den520d = LoadOrDie(data_dir, "den520d.map");
  benchmark::RegisterBenchmark("BM_LacamRandom32", RunLacam, random32)
      ->Arg(100)
      ->Arg(200)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_LacamWarehouse", RunLacam, warehouse)
      ->Arg(1000)
      ->Unit(benchmark::kMillisecond)
      ->Iterations(2);
  benchmark::RegisterBenchmark("BM_LacamDen520d", RunLacam, den520d)
      ->Arg(500)
      ->Unit(benchmark::kMillisecond)
      ->Iterations(2);
  benchmark::RegisterBenchmark("BM_EecbsRandom32", RunEecbs, random32)
      ->Arg(50)
      ->Arg(100)
      ->Unit(benchmark::kMillisecond);
}

}  // namespace fleetnav::planner::bench
