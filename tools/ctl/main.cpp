// fleetnavctl: the operator CLI. Wiring only: flags -> command functions in fleetnav_ctl.
#include <grpcpp/create_channel.h>

#include <CLI/CLI.hpp>
#include <iostream>

#include "fleetnav/core/version.hpp"
#include "fleetnav/ctl/commands.hpp"
#include "fleetnav/ctl/completion.hpp"
#include "fleetnav/ctl/outcome.hpp"
#include "fleetnav/ctl/sim_commands.hpp"
#include "fleetnav/proto/channel_credentials.hpp"
#include "fleetnav/proto/server_target.hpp"

int main(int argc, char** argv) {
  CLI::App app{"fleetnavctl: operate a fleetnav fleet server"};
  app.require_subcommand(1);
  // Global flags may come anywhere on the line: a subcommand hands what it does not know on.
  app.fallthrough();
  app.set_version_flag("--version", std::string(fleetnav::Version()));
  std::string server = "127.0.0.1:50051";
  std::string token;
  bool json = false;
  double timeout_s = 10.0;
  app.add_option("--server", server,
                 "fleetnavd address, or its replicas' IP:port list separated by commas (or "
                 "FLEETNAV_SERVER)")
      ->envname("FLEETNAV_SERVER")
      ->capture_default_str();
  app.add_option("--token", token, "operator bearer token (or FLEETNAV_TOKEN)")
      ->envname("FLEETNAV_TOKEN");
  fleetnav::ClientTlsFiles tls;
  app.add_option("--tls-ca", tls.ca_path,
                 "connect with TLS, trusting this CA for fleetnavd's certificate (or "
                 "FLEETNAV_TLS_CA); plaintext without it")
      ->envname("FLEETNAV_TLS_CA");
  app.add_option("--tls-server-name", tls.server_name,
                 "the name fleetnavd's certificate must carry, when not the --server host");
  app.add_flag("--json", json, "print JSON for scripts instead of tables");
  app.add_option("--timeout-s", timeout_s, "deadline of each call, > 0")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();

  CLI::App* map = app.add_subcommand("map", "maps: import, list, export, render, delete");
  map->require_subcommand(1);
  std::string map_id, yaml_path, description;
  uint32_t version = 0;
  CLI::App* map_import = map->add_subcommand("import", "upload a map_server YAML + PGM");
  map_import->add_option("--id", map_id, "map id ([a-z0-9_-]{1,64})")->required();
  map_import->add_option("yaml", yaml_path, "map_server YAML file")->required();
  map_import->add_option("--description", description, "free text");
  CLI::App* map_list = map->add_subcommand("list", "list maps (latest versions)");
  CLI::App* map_export = map->add_subcommand("export", "download a map as map_server YAML + PGM");
  map_export->add_option("--id", map_id, "map id")->required();
  map_export->add_option("--version", version, "version (0 = latest)");
  map_export->add_option("yaml", yaml_path, "output YAML path (PGM written beside it)")->required();
  CLI::App* map_render =
      map->add_subcommand("render", "draw a map with its markers and routes as a PNG");
  std::string png_path;
  int pixels_per_cell = 0;
  map_render->add_option("map_id", map_id, "map id")->required();
  map_render->add_option("png", png_path, "output PNG path")
      ->required()
      ->check(CLI::Validator(
          [](const std::string& path) -> std::string {
            return path.size() > 4 && path.substr(path.size() - 4) == ".png"
                       ? ""
                       : "'" + path + "' must end in .png (the only format written)";
          },
          "PATH.png"));
  map_render->add_option("--version", version, "map version (0 = latest)");
  map_render
      ->add_option("--pixels-per-cell", pixels_per_cell,
                   "image pixels per grid cell, 1..64 (default: longer side about 1600 px)")
      ->check(CLI::Range(1, 64));
  CLI::App* map_delete = map->add_subcommand("delete", "delete every version of a map");
  map_delete->add_option("--id", map_id, "map id")->required();

  CLI::App* zones =
      app.add_subcommand("zones", "zones of a map (no-go, speed limit, one at a time)");
  zones->require_subcommand(1);
  std::string zone_map;
  CLI::App* zones_put = zones->add_subcommand("put", "upload a zone YAML as a new version");
  zones_put->add_option("--map", zone_map, "map id (default: the file's `map:`)");
  zones_put->add_option("yaml", yaml_path, "zone YAML file")->required();
  CLI::App* zones_get = zones->add_subcommand("get", "print a map's zones as YAML");
  zones_get->add_option("--map", zone_map, "map id")->required();
  zones_get->add_option("--version", version, "version (0 = latest)");
  CLI::App* zones_list = zones->add_subcommand("list", "list the maps that have zones");
  CLI::App* zones_delete = zones->add_subcommand("delete", "delete every version of a map's zones");
  zones_delete->add_option("--map", zone_map, "map id")->required();
  fleetnav::ctl::StopTarget stop_target;
  std::string stop_reason;
  CLI::App* stop = app.add_subcommand(
      "stop", "stop every robot (--all) or those in or entering a zone (not a safety e-stop)");
  CLI::App* resume = app.add_subcommand("resume", "clear a stop made with `stop`");
  for (CLI::App* command : {stop, resume}) {
    CLI::Option* all = command->add_flag("--all", stop_target.whole_fleet, "the whole fleet");
    CLI::Option* zone = command->add_option("--zone", stop_target.zone, "a zone's name");
    command->add_option("--map", stop_target.map_id,
                        "the zone's map (needed when several maps have a zone of that name)");
    all->excludes(zone);
    command->callback([command, &stop_target] {
      if (!stop_target.whole_fleet && stop_target.zone.empty()) {
        throw CLI::ValidationError(command->get_name(), "give --all or --zone NAME");
      }
    });
  }
  stop->add_option("--reason", stop_reason, "why, for the log and the other operators");
  CLI::App* stops = app.add_subcommand("stops", "list the stops in force");
  CLI::App* markers = app.add_subcommand("markers", "stripe-marker sets: put, get, delete");
  markers->require_subcommand(1);
  CLI::App* markers_put = markers->add_subcommand("put", "upload a marker YAML as a new version");
  std::string marker_map;
  markers_put->add_option("--map", marker_map, "map id (default: the file's `map:`)");
  markers_put->add_option("yaml", yaml_path, "marker YAML file")->required();
  CLI::App* markers_delete = markers->add_subcommand(
      "delete", "delete every version of a map's marker set (refused while routes use it)");
  markers_delete->add_option("--map", marker_map, "map id")->required();
  CLI::App* markers_get = markers->add_subcommand("get", "print a map's marker set as YAML");
  markers_get->add_option("--map", marker_map, "map id")->required();
  markers_get->add_option("--version", version, "version (0 = latest)");

  CLI::App* routes = app.add_subcommand("routes", "routes: put, get, list, delete");
  routes->require_subcommand(1);
  std::string route_name;
  CLI::App* routes_put = routes->add_subcommand("put", "upload a route YAML as a new version");
  routes_put->add_option("yaml", yaml_path, "route YAML file")->required();
  CLI::App* routes_get = routes->add_subcommand("get", "print a route as YAML");
  routes_get->add_option("name", route_name, "route name")->required();
  CLI::App* routes_list = routes->add_subcommand("list", "list routes");
  CLI::App* routes_delete = routes->add_subcommand(
      "delete", "delete every version of a route (refused while an unfinished job runs it)");
  routes_delete->add_option("name", route_name, "route name")->required();
  routes_list->add_option("--map", marker_map, "only routes on this map");

  CLI::App* jobs =
      app.add_subcommand("job", "jobs: submit, get, list, cancel, pause, resume, watch");
  jobs->require_subcommand(1);
  fleetnav::ctl::SubmitOptions submit;
  std::string job_id, job_state, reason;
  uint32_t page_size = 100;
  bool wait = false;
  CLI::App* job_submit = jobs->add_subcommand("submit", "run a route with a robot");
  CLI::Option* route_option = job_submit->add_option("--route", submit.route_name, "route name");
  CLI::Option* goal_option =
      job_submit->add_option("--goal", submit.goal, "go to X Y YAW_DEG instead (needs --map)")
          ->expected(3);
  CLI::Option* map_option =
      job_submit->add_option("--map", submit.goal_map_id, "the map of --goal");
  route_option->excludes(goal_option);
  goal_option->needs(map_option);
  map_option->needs(goal_option);
  job_submit->add_option("--robot", submit.robot_id, "a given robot (default: any capable one)");
  job_submit->add_option("--priority", submit.priority, "higher first")->capture_default_str();
  job_submit->add_option("--key", submit.idempotency_key,
                         "idempotency key: the same key returns the same job");
  job_submit->add_flag("--requeue-on-robot-lost", submit.requeue_on_robot_lost,
                       "re-queue instead of failing when the robot is lost");
  job_submit->add_flag("--wait", wait, "then follow the job until it ends (like `job watch`)");
  CLI::App* job_get = jobs->add_subcommand("get", "show one job");
  job_get->add_option("job_id", job_id, "job id")->required();
  CLI::App* job_list = jobs->add_subcommand("list", "list jobs");
  job_list->add_option("--state", job_state,
                       "queued|assigned|running|paused|succeeded|failed|cancelled");
  job_list->add_option("--robot", submit.robot_id, "only jobs of this robot");
  job_list->add_option("--page-size", page_size, "jobs per request")->capture_default_str();
  CLI::App* job_cancel = jobs->add_subcommand("cancel", "cancel a job");
  job_cancel->add_option("job_id", job_id, "job id")->required();
  job_cancel->add_option("--reason", reason, "why");
  CLI::App* job_pause =
      jobs->add_subcommand("pause", "stop an assigned or running job where its robot is");
  job_pause->add_option("job_id", job_id, "job id")->required();
  job_pause->add_option("--reason", reason, "why");
  CLI::App* job_resume = jobs->add_subcommand("resume", "let a paused job go on");
  job_resume->add_option("job_id", job_id, "job id")->required();
  CLI::App* job_watch = jobs->add_subcommand("watch", "follow a job live until it ends");
  job_watch->add_option("job_id", job_id, "job id")->required();

  CLI::App* robots = app.add_subcommand(
      "robots", "list robots with state and pose; `robots forget ID` removes an offline one");
  CLI::App* robots_forget = robots->add_subcommand(
      "forget", "remove an offline robot that holds no job from the registry and the store");
  std::string forget_id;
  robots_forget->add_option("robot_id", forget_id, "robot id")->required();
  CLI::App* tokens = app.add_subcommand(
      "tokens", "operator tokens (admin): list them; create and revoke them at run time");
  CLI::App* tokens_create =
      tokens->add_subcommand("create", "make a token and print its secret (shown only once)");
  std::string token_name, token_role;
  tokens_create->add_option("name", token_name, "token name (1-64 of A-Z a-z 0-9 . _ -)")
      ->required();
  tokens_create->add_option("--role", token_role, "viewer, operator or admin")
      ->required()
      ->check(CLI::IsMember({"viewer", "operator", "admin"}));
  CLI::App* tokens_revoke =
      tokens->add_subcommand("revoke", "refuse a created token from the next call on");
  tokens_revoke->add_option("name", token_name, "token name")->required();
  CLI::App* watch = app.add_subcommand("watch", "follow the fleet live");
  double rate_hz = 5.0, duration_s = 0.0;
  int count = 0;
  watch->add_option("--rate-hz", rate_hz, "update rate in Hz, in (0, 100]")
      ->check(CLI::PositiveNumber & CLI::Range(0.0, 100.0))
      ->capture_default_str();
  watch->add_option("--count", count, "stop after this many updates (0 = never)");
  watch->add_option("--duration-s", duration_s, "stop after this long (0 = never)");
  CLI::App* sim = app.add_subcommand("sim", "simulator: ground truth, compare with the server");
  sim->require_subcommand(1);
  std::string sim_address = "127.0.0.1:50061", robot_id;
  sim->add_option("--sim", sim_address, "fleetnav-sim address")->capture_default_str();
  CLI::App* sim_truth = sim->add_subcommand("truth", "print every robot's true pose");
  CLI::App* sim_compare =
      sim->add_subcommand("compare", "the pose fleetnavd holds beside the true pose");
  sim_compare->add_option("--robot", robot_id, "robot id")->required();
  std::string shell;
  CLI::App* completion =
      app.add_subcommand("completion", "print a shell completion script (source it)");
  completion->add_option("shell", shell, "the shell: bash")
      ->check(CLI::IsMember({"bash"}))
      ->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    (void)app.exit(e);
    return static_cast<int>(fleetnav::ctl::ExitCode::kUsage);
  }

  if (completion->parsed()) {
    std::cout << fleetnav::ctl::BashCompletionScript(app, "fleetnavctl");
    return 0;
  }
  absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> credentials =
      fleetnav::MakeChannelCredentials(tls);
  if (!credentials.ok()) {
    std::cerr << "fleetnavctl: " << credentials.status().message() << '\n';
    return static_cast<int>(fleetnav::ctl::ExitCode::kUsage);
  }
  absl::StatusOr<std::string> server_target = fleetnav::ServerTarget(server);
  if (!server_target.ok()) {
    std::cerr << "fleetnavctl: --server: " << server_target.status().message() << '\n';
    return static_cast<int>(fleetnav::ctl::ExitCode::kUsage);
  }
  grpc::ChannelArguments channel_arguments;
  fleetnav::AddTlsChannelArguments(tls, &channel_arguments);
  fleetnav::ctl::CommandContext context{
      grpc::CreateCustomChannel(*server_target, *credentials, channel_arguments), &std::cout, json,
      timeout_s, token};
  absl::Status status;
  if (map_import->parsed()) {
    status = fleetnav::ctl::ImportMap(context, map_id, yaml_path, description);
  } else if (map_list->parsed()) {
    status = fleetnav::ctl::ListMaps(context);
  } else if (map_export->parsed()) {
    status = fleetnav::ctl::ExportMap(context, map_id, version, yaml_path);
  } else if (map_delete->parsed()) {
    status = fleetnav::ctl::DeleteMap(context, map_id);
  } else if (markers_put->parsed()) {
    status = fleetnav::ctl::PutMarkers(context, marker_map, yaml_path);
  } else if (markers_delete->parsed()) {
    status = fleetnav::ctl::DeleteMarkers(context, marker_map);
  } else if (markers_get->parsed()) {
    status = fleetnav::ctl::GetMarkers(context, marker_map, version);
  } else if (stop->parsed()) {
    status = fleetnav::ctl::StopRobots(context, stop_target, stop_reason);
  } else if (resume->parsed()) {
    status = fleetnav::ctl::ResumeRobots(context, stop_target);
  } else if (stops->parsed()) {
    status = fleetnav::ctl::ListStops(context);
  } else if (zones_put->parsed()) {
    status = fleetnav::ctl::PutZones(context, zone_map, yaml_path);
  } else if (zones_get->parsed()) {
    status = fleetnav::ctl::GetZones(context, zone_map, version);
  } else if (zones_list->parsed()) {
    status = fleetnav::ctl::ListZones(context);
  } else if (zones_delete->parsed()) {
    status = fleetnav::ctl::DeleteZones(context, zone_map);
  } else if (routes_put->parsed()) {
    status = fleetnav::ctl::PutRoute(context, yaml_path);
  } else if (routes_get->parsed()) {
    status = fleetnav::ctl::GetRoute(context, route_name);
  } else if (routes_delete->parsed()) {
    status = fleetnav::ctl::DeleteRoute(context, route_name);
  } else if (map_render->parsed()) {
    status = fleetnav::ctl::RenderMap(context, map_id, version, png_path, pixels_per_cell);
  } else if (routes_list->parsed()) {
    status = fleetnav::ctl::ListRoutes(context, marker_map);
  } else if (job_submit->parsed() && submit.route_name.empty() && submit.goal.empty()) {
    std::cerr
        << "fleetnavctl: job submit: give --route NAME, or --goal X Y YAW_DEG with --map ID\n";
    return static_cast<int>(fleetnav::ctl::ExitCode::kUsage);
  } else if (job_submit->parsed()) {
    absl::StatusOr<std::string> id = fleetnav::ctl::SubmitJob(context, submit);
    status = id.status();
    if (id.ok() && wait) status = fleetnav::ctl::WatchJob(context, *id);
  } else if (job_get->parsed()) {
    status = fleetnav::ctl::GetJob(context, job_id);
  } else if (job_list->parsed()) {
    status = fleetnav::ctl::ListJobs(context, job_state, submit.robot_id, page_size);
  } else if (job_cancel->parsed()) {
    status = fleetnav::ctl::CancelJob(context, job_id, reason);
  } else if (job_pause->parsed()) {
    status = fleetnav::ctl::PauseJob(context, job_id, reason);
  } else if (job_resume->parsed()) {
    status = fleetnav::ctl::ResumeJob(context, job_id);
  } else if (job_watch->parsed()) {
    status = fleetnav::ctl::WatchJob(context, job_id);
  } else if (robots_forget->parsed()) {
    status = fleetnav::ctl::ForgetRobot(context, forget_id);
  } else if (robots->parsed()) {
    status = fleetnav::ctl::ListRobots(context);
  } else if (tokens_create->parsed()) {
    status = fleetnav::ctl::CreateToken(context, token_name, token_role);
  } else if (tokens_revoke->parsed()) {
    status = fleetnav::ctl::RevokeToken(context, token_name);
  } else if (tokens->parsed()) {
    status = fleetnav::ctl::ListTokens(context);
  } else if (sim_truth->parsed()) {
    status = fleetnav::ctl::PrintGroundTruth(
        context, grpc::CreateChannel(sim_address, grpc::InsecureChannelCredentials()));
  } else if (sim_compare->parsed()) {
    status = fleetnav::ctl::CompareWithTruth(
        context, grpc::CreateChannel(sim_address, grpc::InsecureChannelCredentials()), robot_id);
  } else if (watch->parsed()) {
    status = fleetnav::ctl::WatchFleet(context, rate_hz, count, duration_s);
  }
  if (!status.ok()) {
    std::cerr << "fleetnavctl: " << fleetnav::ctl::DescribeFailure(status, server, tls.secure())
              << '\n';
  }
  return static_cast<int>(fleetnav::ctl::ExitCodeFor(status));
}
