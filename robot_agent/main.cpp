// fleetnav-agent: the robot daemon. Wiring only: flags -> model, map, markers, localizer,
// HAL and server link -> Agent.
#include <grpcpp/create_channel.h>
#include <spdlog/spdlog.h>
#include <sys/resource.h>

#include <CLI/CLI.hpp>
#include <fstream>
#include <memory>
#include <optional>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/map_io.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/core/version.hpp"
#include "fleetnav/localization/dead_reckoning_localizer.hpp"
#include "fleetnav/localization/samcl_localizer.hpp"
#include "fleetnav/proto/channel_credentials.hpp"
#include "fleetnav/proto/server_target.hpp"
#include "fleetnav/robot_agent/agent.hpp"
#include "fleetnav/robot_agent/fleet_site_source.hpp"
#include "fleetnav/robot_agent/server_link.hpp"
#include "fleetnav/robot_agent/sim_hal.hpp"
#include "fleetnav/robot_agent/telemetry_recorder.hpp"

namespace {

double CpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

int Fail(const std::string& what) {
  spdlog::error("fleetnav-agent: {}", what);
  return 1;
}

/// Every flag of fleetnav-agent.
struct Flags {
  std::string robot_id = "lely1";
  std::string kind = "lely-vector";
  std::string sim_address = "127.0.0.1:50061";
  std::string server_address = "127.0.0.1:50051";
  std::string route_path, map_path, markers_path, record_path;
  std::vector<double> initial_pose;
  size_t particles = 2000;
  uint64_t seed = 1;
  bool ignore_markers = false, no_augmentation = false, no_obstacle_avoidance = false;
  bool steering_odometry = true;
  fleetnav::ClientTlsFiles tls;
  fleetnav::agent::AgentParams params;
  double telemetry_hz = 1.0 / params.telemetry_period_s;
};

void AddFlags(CLI::App& app, Flags* f) {
  app.add_option("--robot-id", f->robot_id, "this robot's id")->capture_default_str();
  app.add_option("--kind", f->kind,
                 "robot kind: lely-vector | mecanum-platform | ackermann-delivery")
      ->capture_default_str();
  app.add_option("--sim", f->sim_address, "fleetnav-sim address (SimService)")
      ->capture_default_str();
  app.add_option("--server", f->server_address,
                 "fleetnavd address (AgentService), or its replicas' IP:port list separated by "
                 "commas; telemetry to an absent server is dropped")
      ->capture_default_str();
  app.add_option("--tls-ca", f->tls.ca_path,
                 "connect to fleetnavd with TLS, trusting this CA (plaintext without it)");
  app.add_option("--tls-cert", f->tls.cert_path,
                 "this robot's client certificate (PEM; its common name must be --robot-id)");
  app.add_option("--tls-key", f->tls.key_path, "the client certificate's private key (PEM)");
  app.add_option("--tls-server-name", f->tls.server_name,
                 "the name fleetnavd's certificate must carry, when not the --server host");
  app.add_option("--route", f->route_path,
                 "route YAML to run once, then exit 0 if every action completed, 1 otherwise; "
                 "without it the agent takes jobs from fleetnavd");
  app.add_option("--map", f->map_path,
                 "map_server YAML of the site: localize with SAMCL on it (without it: odometry "
                 "and gyro only)");
  app.add_option("--markers", f->markers_path,
                 "marker set YAML of the map: calibration markers for SAMCL and marker end "
                 "conditions");
  app.add_option("--initial-pose", f->initial_pose,
                 "the robot's pose in the map at start: x_m y_m yaw_deg (required)")
      ->expected(3)
      ->required();
  app.add_option("--particles", f->particles, "AMCL particles at most (with --map)")
      ->capture_default_str();
  app.add_option("--seed", f->seed, "seed of the particle filter")->capture_default_str();
  app.add_flag("--no-endpoint-augmentation", f->no_augmentation,
               "move actions that reverse the direction of travel turn back on the spot instead "
               "of bending round (the KUKA thesis's baseline without end-point augmentation)");
  app.add_flag("--no-obstacle-avoidance", f->no_obstacle_avoidance,
               "Ackermann free navigation follows its planned path blind, without VFH+ on the "
               "laser (the baseline for obstacles that are not on the map)");
  app.add_flag("--steering-odometry,!--no-steering-odometry", f->steering_odometry,
               "Ackermann robots: odometry turns by the measured steering angle (bicycle model; "
               "the default); --no-steering-odometry: by the rear wheels' difference");
  app.add_flag("--ignore-markers", f->ignore_markers,
               "plain AMCL: do not calibrate on stripe markers (the SAMCL baseline)");
  app.add_option("--max-jobs", f->params.max_jobs,
                 "in job mode, exit after this many jobs have ended (0 = run until the sim ends)");
  app.add_option("--telemetry-hz", f->telemetry_hz, "telemetry rate in robot time (>= 10)")
      ->capture_default_str();
  app.add_option("--stop-after-link-loss-s", f->params.safety.stop_after_link_loss_s,
                 "in job mode, stand (the job held) once fleetnavd has not been heard for this "
                 "long, robot time, until it is heard again (>= 0)")
      ->capture_default_str();
  app.add_option("--record", f->record_path,
                 "append the estimated position of every telemetry message to this CSV "
                 "(f->robot_id,estimate,x,y,t_s: the fleetnav-sim --trajectories format)");
}

/// What the flags make before anything connects: the robot's model, the route to run (job mode
/// without one), where it starts, what it knows of the site and how it localizes.
struct Robot {
  fleetnav::RobotModel model;
  std::optional<fleetnav::Route> route;
  fleetnav::agent::RouteContext context;
  fleetnav::localization::SamclLocalizerParams localizer_params;
  std::unique_ptr<fleetnav::localization::Localizer> localizer;
};

/// The robot from the flags; the reason (for the log, exit code 1) when a file or flag is bad
/// or a given route cannot run here.
absl::StatusOr<Robot> MakeRobot(Flags& flags) {
  const std::string& kind = flags.kind;
  const std::string& route_path = flags.route_path;
  const std::string& map_path = flags.map_path;
  const std::string& markers_path = flags.markers_path;
  const std::vector<double>& initial_pose = flags.initial_pose;
  fleetnav::agent::AgentParams& params = flags.params;
  const double telemetry_hz = flags.telemetry_hz;
  Robot robot;
  absl::StatusOr<fleetnav::RobotModel> model = fleetnav::RobotModelByKind(kind);
  if (!model.ok()) return model.status();
  robot.model = *model;
  std::optional<fleetnav::Route>& route = robot.route;
  if (!route_path.empty()) {
    absl::StatusOr<fleetnav::Route> loaded = fleetnav::LoadRoute(route_path);
    if (!loaded.ok())
      return absl::InvalidArgumentError(absl::StrCat(route_path, ": ", loaded.status().ToString()));
    route = *loaded;
  }
  const fleetnav::Pose2 start(initial_pose[0], initial_pose[1],
                              fleetnav::DegToRad(initial_pose[2]));
  if (!start.IsFinite()) return absl::InvalidArgumentError("--initial-pose: must be finite");
  params.telemetry_period_s = telemetry_hz > 0 ? 1.0 / telemetry_hz : 0.0;
  params.exit_when_done = route.has_value();
  params.modes.move.augment_endpoints = !flags.no_augmentation;
  params.modes.free_navigation.ackermann.avoid_obstacles = !flags.no_obstacle_avoidance;

  robot.context = fleetnav::agent::RouteContext{*model, std::nullopt, nullptr};
  fleetnav::agent::RouteContext& context = robot.context;
  if (!markers_path.empty()) {
    if (map_path.empty()) return absl::InvalidArgumentError("--markers needs --map");
    absl::StatusOr<fleetnav::MarkerSet> markers = fleetnav::LoadMarkerSet(markers_path);
    if (!markers.ok())
      return absl::InvalidArgumentError(
          absl::StrCat(markers_path, ": ", markers.status().ToString()));
    if (route && !markers->map_id.empty() && !route->map_id.empty() &&
        markers->map_id != route->map_id) {
      return absl::InvalidArgumentError(absl::StrCat(
          "route refused before moving: route '", route->name, "' is on map '", route->map_id,
          "' but ", markers_path, " is the marker set of map '", markers->map_id, "'"));
    }
    context.markers = *markers;
  }
  fleetnav::localization::SamclLocalizerParams& lp = robot.localizer_params;
  lp.amcl.max_particles = flags.particles;
  lp.amcl.min_particles = std::min(lp.amcl.min_particles, flags.particles);
  lp.amcl.seed = flags.seed;
  lp.amcl.motion.kinematics = model->kinematics;  // the odometry motion model of its drive
  lp.use_markers = !flags.ignore_markers;
  lp.odometry.ackermann_yaw_from_steering = flags.steering_odometry;
  lp.ultrasonic_range_max_m = params.ultrasonic_range_max_m;
  std::unique_ptr<fleetnav::localization::Localizer>& localizer = robot.localizer;
  if (!map_path.empty()) {
    absl::StatusOr<fleetnav::OccupancyGrid> map = fleetnav::LoadMapServer(map_path);
    if (!map.ok())
      return absl::InvalidArgumentError(absl::StrCat(map_path, ": ", map.status().ToString()));
    context.map = std::make_shared<const fleetnav::OccupancyGrid>(*map);
    auto samcl = fleetnav::localization::SamclLocalizer::Create(
        *model, *map, context.markers.value_or(fleetnav::MarkerSet{}), start, lp);
    if (!samcl.ok())
      return absl::InvalidArgumentError(absl::StrCat("localization: ", samcl.status().ToString()));
    localizer = std::make_unique<fleetnav::localization::SamclLocalizer>(*std::move(samcl));
  } else {
    auto dead_reckoning = fleetnav::localization::DeadReckoningLocalizer::Create(*model, start);
    if (!dead_reckoning.ok()) {
      return absl::InvalidArgumentError(
          absl::StrCat("localization: ", dead_reckoning.status().ToString()));
    }
    localizer = std::make_unique<fleetnav::localization::DeadReckoningLocalizer>(
        *std::move(dead_reckoning));
  }
  // A route this agent cannot run is refused before the robot moves.
  if (route) {
    if (absl::Status s = fleetnav::agent::CheckRoute(*route, context, params.modes); !s.ok()) {
      return absl::InvalidArgumentError(absl::StrCat("route refused before moving: ", s.message()));
    }
  }
  return robot;
}

/// The run's events, calibrations and figures, for the log.
void LogRun(const Flags& flags, const fleetnav::agent::AgentResult& result, uint64_t sent,
            double cpu_s) {
  const bool job_mode = flags.route_path.empty();
  for (const fleetnav::JobEvent& event : result.events) {
    if (event.type == fleetnav::JobEventType::kModeSwitch ||
        event.type == fleetnav::JobEventType::kBumper ||
        event.type == fleetnav::JobEventType::kLocalizationLost) {
      spdlog::info("event: action {}: {}", event.action_index, event.reason);
    }
  }
  for (const auto& c : result.calibrations) {
    spdlog::info(
        "{} marker {} ({}) at t = {:.3f} s, moved {:.3f} m to ({:.3f}, {:.3f}, {:.1f} deg)",
        c.applied ? "calibrated on" : "crossed (not used)", c.marker_id, c.sensor_name,
        c.stamp_ns * 1e-9, c.correction_m, c.pose_in_map.x_m(), c.pose_in_map.y_m(),
        fleetnav::RadToDeg(c.pose_in_map.yaw_rad()));
  }
  const fleetnav::Pose2& end = result.final_pose_in_map;
  const double sim_s = result.sim_time_s;
  spdlog::info(
      "fleetnav-agent: {} after {} ticks; estimated pose ({:.3f}, {:.3f}, {:.2f} deg); "
      "{} telemetry messages; {:.2f} CPU-s for {:.1f} sim-s ({:.1f} % of a core at 1x)",
      job_mode ? std::to_string(result.jobs_finished) + " job(s) ended"
      : result.state == fleetnav::agent::ExecutionState::kSucceeded ? "route succeeded"
      : result.state == fleetnav::agent::ExecutionState::kFailed
          ? "route failed: " + result.failure_reason
          : "stopped",
      result.ticks, end.x_m(), end.y_m(), fleetnav::RadToDeg(end.yaw_rad()), sent, cpu_s, sim_s,
      sim_s > 0 ? 100.0 * cpu_s / sim_s : 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fleetnav-agent: robot daemon (HAL over SimService, telemetry to fleetnavd)"};
  app.set_version_flag("--version", std::string(fleetnav::Version()));
  Flags flags;
  AddFlags(app, &flags);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    (void)app.exit(e);
    return 1;
  }
  absl::StatusOr<Robot> made = MakeRobot(flags);
  if (!made.ok()) return Fail(std::string(made.status().message()));
  Robot& robot_setup = *made;
  const fleetnav::RobotModel* model = &robot_setup.model;
  const std::optional<fleetnav::Route>& route = robot_setup.route;
  const fleetnav::agent::RouteContext& context = robot_setup.context;
  const fleetnav::localization::SamclLocalizerParams& lp = robot_setup.localizer_params;
  std::unique_ptr<fleetnav::localization::Localizer>& localizer = robot_setup.localizer;
  const fleetnav::agent::AgentParams& params = flags.params;
  const std::string& robot_id = flags.robot_id;
  const std::string& kind = flags.kind;
  const std::string& sim_address = flags.sim_address;
  const std::string& server_address = flags.server_address;
  const fleetnav::ClientTlsFiles& tls = flags.tls;
  const std::string& record_path = flags.record_path;

  // Both links retry a refused connection within a second (gRPC's own reconnect back-off grows
  // to 120 s by default): a robot whose link dropped is back as soon as the other end is.
  grpc::ChannelArguments quick_reconnect;
  quick_reconnect.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, 200);
  quick_reconnect.SetInt(GRPC_ARG_MIN_RECONNECT_BACKOFF_MS, 200);
  quick_reconnect.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, 1000);
  auto sim_channel =
      grpc::CreateCustomChannel(sim_address, grpc::InsecureChannelCredentials(), quick_reconnect);
  // A simulator that has just started on a loaded machine may take a while to answer.
  if (absl::Status s =
          fleetnav::agent::SimHal::CheckRobotKind(sim_channel, robot_id, kind, /*timeout_s=*/30.0);
      !s.ok()) {
    return Fail(s.ToString());
  }
  // What this agent can execute: a job needs every one of its route's action types here.
  fleetnav::RobotIdentity identity{robot_id, *model, fleetnav::agent::SupportedActionTypes(*model),
                                   "0.2.0"};
  identity.segment_clearances = true;  // the executor stands before a clearance's gate
  identity.planned_paths = true;       // it drives a free-navigation action through a planned path
  absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> server_credentials =
      fleetnav::MakeChannelCredentials(tls);
  if (!server_credentials.ok()) return Fail(server_credentials.status().ToString());
  // One fleetnavd, or the list of its replicas: the link takes the first that answers.
  absl::StatusOr<std::string> server_target = fleetnav::ServerTarget(server_address);
  if (!server_target.ok())
    return Fail(absl::StrCat("--server: ", server_target.status().message()));
  grpc::ChannelArguments server_arguments = quick_reconnect;
  fleetnav::AddTlsChannelArguments(tls, &server_arguments);
  auto server_channel =
      grpc::CreateCustomChannel(*server_target, *server_credentials, server_arguments);
  // On the simulator the agent takes part in the lockstep: fleetnavd takes in each tick
  // before the simulator advances, so that a run replays exactly (docs/simulator.md).
  fleetnav::agent::ServerLinkParams link_params;
  link_params.lockstep = true;
  fleetnav::agent::ServerLink link(server_channel, identity, link_params);
  fleetnav::agent::SimHal hal(sim_channel, robot_id);
  std::ofstream record;
  std::optional<fleetnav::agent::TelemetryRecorder> recorder;
  if (!record_path.empty()) {
    record.open(record_path, std::ios::app);
    if (!record) return Fail(absl::StrCat("cannot write --record file '", record_path, "'"));
    recorder.emplace(robot_id, &record, &link);
  }
  fleetnav::agent::TelemetrySink* telemetry =
      recorder ? static_cast<fleetnav::agent::TelemetrySink*>(&*recorder) : &link;
  fleetnav::agent::AgentPorts ports{&hal, localizer.get(), telemetry,
                                    route.has_value() ? nullptr : &link};
  // In job mode each job brings its map and marker set, at the versions its route was
  // validated against: the agent localizes with SAMCL on them.
  fleetnav::agent::FleetSiteSource sites(server_channel);
  if (!route) {
    ports.sites = &sites;
    ports.make_localizer = [&model, lp](const fleetnav::agent::SiteData& site,
                                        const fleetnav::Pose2& start)
        -> absl::StatusOr<std::unique_ptr<fleetnav::localization::Localizer>> {
      auto samcl = fleetnav::localization::SamclLocalizer::Create(
          *model, *site.map, site.markers.value_or(fleetnav::MarkerSet{}), start, lp);
      if (!samcl.ok()) return samcl.status();
      return std::make_unique<fleetnav::localization::SamclLocalizer>(*std::move(samcl));
    };
  }
  fleetnav::agent::Agent agent(context, ports, route, params);
  spdlog::info("fleetnav-agent '{}' ({}) attached to {}, reporting to {}, localizing with {}",
               robot_id, kind, sim_address, server_address,
               flags.map_path.empty() ? "odometry" : (flags.ignore_markers ? "AMCL" : "SAMCL"));
  const double cpu_start_s = CpuSeconds();
  absl::StatusOr<fleetnav::agent::AgentResult> result = agent.Run();
  const double cpu_s = CpuSeconds() - cpu_start_s;
  link.Close();
  if (!result.ok()) return Fail(result.status().ToString());
  LogRun(flags, *result, link.sent(), cpu_s);
  if (route.has_value() && result->state != fleetnav::agent::ExecutionState::kSucceeded) {
    return Fail(result->state == fleetnav::agent::ExecutionState::kFailed
                    ? "route failed: " + result->failure_reason
                    : "the simulation ended before the route did");
  }
  return 0;
}
