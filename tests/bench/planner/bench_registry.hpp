#pragma once

#include <string>

namespace fleetnav::planner::bench {

/// Registers the MAPF benchmarks on the MovingAI maps of `data_dir`; exits with status 2 and a
/// message naming the file when a map is missing or malformed.
void RegisterMapfBenchmarks(const std::string& data_dir);
/// Registers the mixed-fleet kinematic benchmarks on `data_dir`/random-32-32-10.map.
void RegisterKinematicBenchmarks(const std::string& data_dir);

}  // namespace fleetnav::planner::bench
