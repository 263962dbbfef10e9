// Hot paths of the simulator: one sensor frame with a 270-beam laser in the supermarket, and
// one control tick of each kind of robot.
#include <benchmark/benchmark.h>

#include "fleetnav/sim/simulation.hpp"

namespace fleetnav::sim {
namespace {

std::unique_ptr<Simulation> Make(const std::string& world_file) {
  absl::StatusOr<WorldDescription> world =
      LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/" + world_file);
  if (!world.ok()) return nullptr;
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(*world, SimulationParams{});
  if (!sim.ok()) return nullptr;
  for (const RobotSpawn& spawn : world->robots) {
    (void)(*sim)->AddRobot(spawn.robot_id, spawn.kind_name, spawn.pose);
  }
  return std::move(*sim);
}

void BM_SenseOmniWithLaser(benchmark::State& state) {
  std::unique_ptr<Simulation> sim = Make("supermarket.yaml");
  for (auto _ : state) benchmark::DoNotOptimize(sim->Sense("omni1"));  // tick 0: a laser tick
}
BENCHMARK(BM_SenseOmniWithLaser);

void BM_SenseLelyInTheBarn(benchmark::State& state) {
  std::unique_ptr<Simulation> sim = Make("barn.yaml");
  for (auto _ : state) benchmark::DoNotOptimize(sim->Sense("lely1"));
}
BENCHMARK(BM_SenseLelyInTheBarn);

void BM_AdvanceOneTick(benchmark::State& state, const char* world, const char* robot) {
  std::unique_ptr<Simulation> sim = Make(world);
  ActuatorCommand command;
  command.drive = Twist2{0.3, 0.0, 0.1};
  (void)sim->Command(robot, command);
  for (auto _ : state) sim->Advance();
}
BENCHMARK_CAPTURE(BM_AdvanceOneTick, lely, "barn.yaml", "lely1");
BENCHMARK_CAPTURE(BM_AdvanceOneTick, omni, "supermarket.yaml", "omni1");
BENCHMARK_CAPTURE(BM_AdvanceOneTick, ackermann, "delivery_yard.yaml", "delivery1");

}  // namespace
}  // namespace fleetnav::sim

BENCHMARK_MAIN();
