// fleetnavctl: the operator CLI. Wiring only: flags -> command functions in fleetnav_ctl.
#include <grpcpp/create_channel.h>

#include <iostream>

#include <CLI/CLI.hpp>

#include "fleetnav/ctl/commands.hpp"
#include "fleetnav/ctl/sim_commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"fleetnavctl: operate a fleetnav fleet server"};
  app.require_subcommand(1);
  std::string server = "127.0.0.1:50051";
  bool json = false;
  double timeout_s = 10.0;
  app.add_option("--server", server, "fleetnavd address")->capture_default_str();
  app.add_flag("--json", json, "print JSON for scripts instead of tables");
  app.add_option("--timeout-s", timeout_s, "deadline of each call")->capture_default_str();

  CLI::App* map = app.add_subcommand("map", "maps: import, list, export, delete");
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
  CLI::App* map_delete = map->add_subcommand("delete", "delete every version of a map");
  map_delete->add_option("--id", map_id, "map id")->required();

  CLI::App* robots = app.add_subcommand("robots", "list robots with state and pose");
  CLI::App* watch = app.add_subcommand("watch", "follow the fleet live");
  double rate_hz = 5.0, duration_s = 0.0;
  int count = 0;
  watch->add_option("--rate-hz", rate_hz, "update rate")->capture_default_str();
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
  CLI11_PARSE(app, argc, argv);

  fleetnav::ctl::CommandContext context{
      grpc::CreateChannel(server, grpc::InsecureChannelCredentials()), &std::cout, json,
      timeout_s};
  absl::Status status;
  if (map_import->parsed()) {
    status = fleetnav::ctl::ImportMap(context, map_id, yaml_path, description);
  } else if (map_list->parsed()) {
    status = fleetnav::ctl::ListMaps(context);
  } else if (map_export->parsed()) {
    status = fleetnav::ctl::ExportMap(context, map_id, version, yaml_path);
  } else if (map_delete->parsed()) {
    status = fleetnav::ctl::DeleteMap(context, map_id);
  } else if (robots->parsed()) {
    status = fleetnav::ctl::ListRobots(context);
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
    std::cerr << "fleetnavctl: " << status.ToString() << '\n';
    return 1;
  }
  return 0;
}
