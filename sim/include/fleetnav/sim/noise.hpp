#pragma once

#include <cstdint>
#include <random>
#include <string_view>

namespace fleetnav::sim {

/// A seed for one robot's one sensor, derived from the simulation seed so that every
/// (robot, sensor) pair has its own stream: adding a robot never changes another's noise.
uint64_t NoiseSeed(uint64_t simulation_seed, std::string_view robot_id, std::string_view sensor);

/// A seeded Gaussian noise stream.
class NoiseStream {
 public:
  explicit NoiseStream(uint64_t seed) : engine_(seed) {}
  double Gaussian(double stddev) { return stddev > 0.0 ? stddev * normal_(engine_) : 0.0; }
  double Uniform() { return uniform_(engine_); }

 private:
  std::mt19937_64 engine_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

}  // namespace fleetnav::sim
