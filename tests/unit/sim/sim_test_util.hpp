#pragma once

#include <gtest/gtest.h>

#include <memory>

#include "fleetnav/sim/simulation.hpp"

namespace fleetnav::sim::testing {

/// A world with nothing in it but the floor (extent only).
inline WorldDescription EmptyWorld() {
  WorldDescription world;
  world.name = "empty";
  world.min_corner_m = Eigen::Vector2d(-50, -50);
  world.max_corner_m = Eigen::Vector2d(50, 50);
  return world;
}

inline std::unique_ptr<Simulation> MakeSimulation(uint64_t seed, SimulationParams params = {}) {
  params.seed = seed;
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(EmptyWorld(), params);
  EXPECT_TRUE(sim.ok()) << sim.status();
  return sim.ok() ? std::move(*sim) : nullptr;
}

inline ActuatorCommand TwistCommand(double vx_mps, double yaw_rate_radps) {
  ActuatorCommand command;
  command.drive = Twist2{vx_mps, 0.0, yaw_rate_radps};
  return command;
}

}  // namespace fleetnav::sim::testing
