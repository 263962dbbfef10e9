// fleetnav-sim-bench: how fast the simulator runs a mixed fleet in lockstep. N robots (40 %
// Lely, 30 % omni, 30 % Ackermann) each in a 10 m cell of a generated site with a few
// obstacles, every sensor on (270-beam lasers at 10 Hz), each driven by a trivial in-process
// agent on its own thread through the Lockstep barrier. Prints the real-time factor and the
// wall time per tick spent in physics and in sensors.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "fleetnav/core/version.hpp"
#include "fleetnav/sim/lockstep.hpp"
#include "fleetnav/sim/simulation.hpp"

namespace {

using fleetnav::sim::BoxObstacle;
using fleetnav::sim::CylinderObstacle;
using fleetnav::sim::WorldDescription;

constexpr double kCellM = 10.0;

WorldDescription BenchWorld(int robots, int columns) {
  const int rows = (robots + columns - 1) / columns;
  WorldDescription world;
  world.name = "bench";
  world.min_corner_m = Eigen::Vector2d(0, 0);
  world.max_corner_m = Eigen::Vector2d(columns * kCellM, rows * kCellM);
  const Eigen::Vector2d size = world.max_corner_m;
  world.boxes.push_back({"wall", {0.5 * size.x(), -0.1}, {size.x(), 0.2}, 0.0, 2.5});
  world.boxes.push_back({"wall", {0.5 * size.x(), size.y() + 0.1}, {size.x(), 0.2}, 0.0, 2.5});
  world.boxes.push_back({"wall", {-0.1, 0.5 * size.y()}, {0.2, size.y()}, 0.0, 2.5});
  world.boxes.push_back({"wall", {size.x() + 0.1, 0.5 * size.y()}, {0.2, size.y()}, 0.0, 2.5});
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      const Eigen::Vector2d corner(c * kCellM, r * kCellM);
      world.boxes.push_back({"box", corner + Eigen::Vector2d(1.0, 1.0), {1.0, 0.6}, 0.3, 1.0});
      world.cylinders.push_back({"post", corner + Eigen::Vector2d(9.0, 9.0), 0.15, 2.0});
      world.stripes.push_back({r * columns + c,
                               {corner + Eigen::Vector2d(2, 5), corner + Eigen::Vector2d(8, 5)},
                               0.05});
    }
  }
  return world;
}

const char* KindOf(int i) {
  const int slot = i % 10;
  if (slot < 4) return "lely-vector";
  if (slot < 7) return "mecanum-platform";
  return "ackermann-delivery";
}

fleetnav::ActuatorCommand TrivialCommand(const std::string& kind, uint64_t tick) {
  fleetnav::ActuatorCommand command;
  command.tick = tick;
  if (kind == "lely-vector") {
    command.drive = fleetnav::Twist2{0.3, 0.0, 0.1};
  } else if (kind == "mecanum-platform") {
    command.drive = fleetnav::Twist2{0.3, 0.1, 0.1};
  } else {
    command.drive = fleetnav::AckermannDrive{0.5, 0.25};
  }
  return command;
}

}  // namespace

int main(int argc, char** argv) {
  int robots = 10;
  double seconds = 30.0;
  bool json = false;
  uint64_t seed = 1;
  CLI::App app{"fleetnav-sim-bench: lockstep simulator throughput for a mixed fleet"};
  app.set_version_flag("--version", std::string(fleetnav::Version()));
  app.add_option("--robots", robots, "number of robots")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--seconds", seconds, "simulated seconds")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--seed", seed, "random seed")->capture_default_str();
  app.add_flag("--json", json, "print one JSON object");
  bool kinematic_omni = false;
  app.add_flag("--kinematic-omni", kinematic_omni,
               "mecanum platforms as kinematic bodies instead of physical ones");
  bool kinematic_ackermann = false;
  app.add_flag("--kinematic-ackermann", kinematic_ackermann,
               "Ackermann robots as kinematic bodies instead of physical ones");
  CLI11_PARSE(app, argc, argv);

  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(robots))));
  fleetnav::sim::SimulationParams params;
  params.seed = seed;
  params.kinematic_omni = kinematic_omni;
  params.kinematic_ackermann = kinematic_ackermann;
  params.exteroceptive.omni_laser.beams = 270;  // the benchmark's 270-beam lasers
  params.exteroceptive.ackermann_laser.beams = 270;
  auto simulation = fleetnav::sim::Simulation::Create(BenchWorld(robots, columns), params);
  if (!simulation.ok()) {
    std::fprintf(stderr, "%s\n", simulation.status().ToString().c_str());
    return 1;
  }
  std::vector<std::string> kinds;
  for (int i = 0; i < robots; ++i) {
    const Eigen::Vector2d cell((i % columns) * kCellM, (i / columns) * kCellM);
    const std::string id = "r" + std::to_string(i);
    kinds.push_back(KindOf(i));
    absl::Status added =
        (*simulation)
            ->AddRobot(id, kinds.back(), fleetnav::Pose2(cell.x() + 3.5, cell.y() + 2.5, 0.0));
    if (!added.ok()) {
      std::fprintf(stderr, "%s\n", added.ToString().c_str());
      return 1;
    }
  }
  fleetnav::sim::LockstepParams lockstep_params;
  lockstep_params.min_attached = robots;
  lockstep_params.max_sim_time_s = seconds;
  fleetnav::sim::Lockstep lockstep(simulation->get(), lockstep_params);

  std::vector<std::thread> agents;
  for (int i = 0; i < robots; ++i) {
    auto attachment = lockstep.Attach("r" + std::to_string(i));
    if (!attachment.ok()) {
      std::fprintf(stderr, "%s\n", attachment.status().ToString().c_str());
      return 1;
    }
    agents.emplace_back(
        [attachment = std::move(*attachment), kind = kinds[static_cast<size_t>(i)]]() mutable {
          while (std::optional<fleetnav::SensorFrame> frame = attachment->WaitFrame()) {
            (void)attachment->Submit(TrivialCommand(kind, frame->tick));
          }
        });
  }
  const auto start = std::chrono::steady_clock::now();
  lockstep.Run();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (std::thread& agent : agents) agent.join();

  const fleetnav::sim::SimulationTiming& timing = (*simulation)->timing();
  const double sim_s = static_cast<double>(lockstep.now_ns()) * 1e-9;
  const double ticks = static_cast<double>(std::max<uint64_t>(1, timing.ticks));
  const double rtf = sim_s / wall_s;
  const double physics_ms = timing.physics_s * 1e3 / ticks;
  const double sensors_ms = timing.sensors_s * 1e3 / ticks;
  if (json) {
    std::printf(
        "{\"robots\": %d, \"sim_seconds\": %.3f, \"wall_seconds\": %.3f, \"ticks\": %llu, "
        "\"real_time_factor\": %.2f, \"physics_ms_per_tick\": %.3f, \"sensors_ms_per_tick\": "
        "%.3f, \"omni_bodies\": \"%s\", \"ackermann_bodies\": \"%s\"}\n",
        robots, sim_s, wall_s, static_cast<unsigned long long>(timing.ticks), rtf, physics_ms,
        sensors_ms, kinematic_omni ? "kinematic" : "physical",
        kinematic_ackermann ? "kinematic" : "physical");
  } else {
    std::printf(
        "robots %d: %.1f s simulated in %.2f s wall = %.1fx real time; physics %.3f ms/tick, "
        "sensors %.3f ms/tick (%s omni bodies, %s Ackermann bodies)\n",
        robots, sim_s, wall_s, rtf, physics_ms, sensors_ms,
        kinematic_omni ? "kinematic" : "physical", kinematic_ackermann ? "kinematic" : "physical");
  }
  return 0;
}
