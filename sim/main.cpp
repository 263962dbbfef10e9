// fleetnav-sim: the ODE simulator. Wiring only: flags -> world -> SimServer (or map export).
#include <pthread.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <thread>

#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/map_io.hpp"
#include "fleetnav/core/port_file.hpp"
#include "fleetnav/core/stop_signals.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/core/version.hpp"
#include "fleetnav/sim/sim_server.hpp"
#include "fleetnav/sim/world_rasterizer.hpp"
#include "fleetnav/sim/world_render.hpp"

namespace {

int ExportMap(const fleetnav::sim::WorldDescription& world, const std::string& directory,
              double resolution_m) {
  std::filesystem::create_directories(directory);
  absl::StatusOr<fleetnav::OccupancyGrid> grid = fleetnav::sim::RasterizeWorld(world, resolution_m);
  if (!grid.ok()) {
    spdlog::error("rasterize: {}", grid.status().ToString());
    return 1;
  }
  const std::string stem = (std::filesystem::path(directory) / world.name).string();
  absl::Status saved = fleetnav::SaveMapServer(*grid, stem + ".yaml");
  if (saved.ok()) {
    saved = fleetnav::SaveMarkerSet(fleetnav::sim::MarkerSetOf(world, world.name),
                                    stem + ".markers.yaml");
  }
  if (!saved.ok()) {
    spdlog::error("export: {}", saved.ToString());
    return 1;
  }
  spdlog::info("wrote {0}.yaml, {0}.pgm and {0}.markers.yaml ({1} x {2} cells)", stem,
               grid->width(), grid->height());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  sigset_t stop_signals = fleetnav::BlockStopSignals();

  fleetnav::sim::SimServerParams params;
  std::string world_path;
  std::string export_dir;
  double map_resolution_m = 0.05;
  std::string port_file;
  CLI::App app{"fleetnav-sim: ODE simulator serving SimService in lockstep"};
  app.set_version_flag("--version", std::string(fleetnav::Version()));
  app.add_option("--world", world_path, "world YAML file")->required();
  app.add_option("--listen", params.listen_address, "address to serve on (port 0 = any)")
      ->capture_default_str();
  app.add_option("--seed", params.simulation.seed, "random seed")->capture_default_str();
  app.add_option("--physics-step-s", params.simulation.physics_step_s, "ODE step")
      ->capture_default_str();
  app.add_option("--control-period-s", params.simulation.control_period_s, "lockstep tick")
      ->capture_default_str();
  app.add_flag("--kinematic-omni", params.simulation.kinematic_omni,
               "move mecanum platforms kinematically (no wheels, casters or contact forces; "
               "cheaper, for large fleets) instead of as physical ODE bodies");
  app.add_flag("--kinematic-ackermann", params.simulation.kinematic_ackermann,
               "move Ackermann robots kinematically (the bicycle model: no tyres or contact "
               "forces; cheaper, for large fleets) instead of as physical ODE bodies");
  app.add_option("--real-time-factor", params.lockstep.real_time_factor,
                 "cap on sim/wall speed (0 = as fast as agents answer)")
      ->capture_default_str();
  app.add_option("--min-agents", params.lockstep.min_attached,
                 "ticks advance only while this many agents are attached")
      ->capture_default_str();
  app.add_option("--max-sim-time-s", params.lockstep.max_sim_time_s, "stop after (0 = never)")
      ->capture_default_str();
  app.add_option("--server-tick-every", params.lockstep.server_tick_every,
                 "in lockstep, agents report to fleetnavd every N ticks (on the last of each N "
                 "and before a hold; 1 = every tick)")
      ->capture_default_str();
  app.add_option("--start-unix-ms", params.start_unix_ms,
                 "the calendar at sim time 0, ms since 1970-01-01 UTC (0 = the wall clock at "
                 "start); fleetnavd with --clock sim stamps its records with it plus sim time")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_flag("--hold", params.lockstep.start_held,
               "start held at tick 0: ticks advance only as far as the RunUntil RPC asks (how "
               "fleetnav-scenario replays a run tick for tick)");
  app.add_option("--export-map", export_dir,
                 "write the world's map (map_server YAML+PGM) and markers to DIR, then exit");
  app.add_option("--map-resolution-m", map_resolution_m, "resolution of --export-map")
      ->capture_default_str();
  app.add_option("--port-file", port_file, "write the bound port to this file once serving");
  std::string render_path;
  std::string trajectory_path;
  double render_scale = 40.0;
  app.add_option("--render", render_path,
                 "draw the world (and --trajectories) to this .png or .svg file, then exit");
  app.add_option("--trajectories", trajectory_path,
                 "CSV of robot_id,truth|estimate,x,y to draw with --render");
  app.add_option("--render-px-per-m", render_scale, "scale of --render")->capture_default_str();
  std::string record_path;
  double record_hz = 10.0;
  app.add_option("--record-truth", record_path,
                 "append every robot's true position at --record-truth-hz of sim time to this CSV "
                 "(robot_id,truth,x,y,t_s,yaw_rad: the --trajectories format and the yaw)");
  app.add_option("--record-truth-hz", record_hz, "rate of --record-truth (at most the tick rate)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  absl::StatusOr<fleetnav::sim::WorldDescription> world = fleetnav::sim::LoadWorld(world_path);
  if (!world.ok()) {
    spdlog::error("{}", world.status().ToString());
    return 1;
  }
  if (!export_dir.empty()) return ExportMap(*world, export_dir, map_resolution_m);
  if (params.start_unix_ms == 0) params.start_unix_ms = fleetnav::SystemClock().UnixMs();
  if (!render_path.empty()) {
    std::vector<fleetnav::sim::TrajectoryTrace> traces;
    if (!trajectory_path.empty()) {
      absl::StatusOr<std::vector<fleetnav::sim::TrajectoryTrace>> loaded =
          fleetnav::sim::LoadTrajectoriesCsv(trajectory_path);
      if (!loaded.ok()) {
        spdlog::error("{}", loaded.status().ToString());
        return 1;
      }
      traces = std::move(*loaded);
    }
    fleetnav::sim::RenderParams render_params;
    render_params.pixels_per_m = render_scale;
    absl::Status rendered = fleetnav::sim::RenderWorld(*world, traces, render_path, render_params);
    if (!rendered.ok()) {
      spdlog::error("{}", rendered.ToString());
      return 1;
    }
    spdlog::info("wrote {}", render_path);
    return 0;
  }

  std::ofstream record;  // outlives the server, whose loop writes to it
  if (!record_path.empty()) {
    record.open(record_path, std::ios::app);
    if (!record) {
      spdlog::error("fleetnav-sim: cannot write --record-truth file '{}'", record_path);
      return 1;
    }
  }
  fleetnav::sim::SimServer server(*world, params);
  absl::StatusOr<int> port = server.Start();
  if (!port.ok()) {
    spdlog::error("fleetnav-sim: {}", port.status().ToString());
    return 1;
  }
  if (!record_path.empty()) {
    const int every_ticks = std::max(
        1, static_cast<int>(std::lround(1.0 / record_hz / params.simulation.control_period_s)));
    server.lockstep().SetTickObserver([&record, every_ticks](const fleetnav::sim::Simulation& sim) {
      if (sim.tick() % static_cast<uint64_t>(every_ticks) != 0) return;
      const fleetnav::sim::GroundTruthSnapshot truth = sim.GroundTruth();
      for (const fleetnav::sim::RobotTruth& robot : truth.robots) {
        record << robot.robot_id << ",truth," << robot.pose.x_m() << ',' << robot.pose.y_m() << ','
               << truth.sim_time_ns * 1e-9 << ',' << robot.pose.yaw_rad() << '\n';
      }
    });
  }
  spdlog::info("fleetnav-sim: world '{}' with {} robot(s) on port {}", world->name,
               world->robots.size(), *port);
  if (!port_file.empty()) {
    if (absl::Status written = fleetnav::WritePortFile(port_file, *port); !written.ok()) {
      spdlog::warn("fleetnav-sim: {}", std::string(written.message()));
    }
  }
  // Stop on a signal, or when the loop ends by itself (max sim time).
  std::thread signal_waiter([&] {
    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    server.lockstep().Stop();
  });
  server.WaitForLoop();
  spdlog::info("fleetnav-sim: stopped at sim time {:.2f} s", server.lockstep().now_ns() * 1e-9);
  server.Shutdown();
  pthread_kill(signal_waiter.native_handle(), SIGTERM);
  signal_waiter.join();
  return 0;
}
