// planner_bench [--data_dir=DIR] [Google Benchmark flags]: the single-robot benchmarks always;
// the multi-robot ones on the MovingAI benchmark maps (random-32-32-20, random-32-32-10,
// warehouse-20-40-10-2-2, den520d) when --data_dir names the folder that holds them.
#include <benchmark/benchmark.h>

#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "bench_registry.hpp"

int main(int argc, char** argv) {
  constexpr std::string_view kFlag = "--data_dir=";
  std::string data_dir;
  std::vector<char*> remaining;
  for (int i = 0; i < argc; ++i) {
    const std::string_view arg(argv[i]);
    if (arg.substr(0, kFlag.size()) == kFlag) {
      data_dir = std::string(arg.substr(kFlag.size()));
    } else {
      remaining.push_back(argv[i]);
    }
  }
  if (data_dir.empty()) {
    std::cerr << "planner_bench: no --data_dir=DIR given, so the multi-robot benchmarks on the "
                 "MovingAI maps are not run (pass the folder that holds random-32-32-20.map, "
                 "random-32-32-10.map, warehouse-20-40-10-2-2.map and den520d.map)\n";
  } else {
    fleetnav::planner::bench::RegisterMapfBenchmarks(data_dir);
    fleetnav::planner::bench::RegisterKinematicBenchmarks(data_dir);
  }
  int remaining_argc = static_cast<int>(remaining.size());
  benchmark::Initialize(&remaining_argc, remaining.data());
  if (benchmark::ReportUnrecognizedArguments(remaining_argc, remaining.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
