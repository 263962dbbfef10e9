// fleetnav-agent: the robot daemon. Wiring only: flags -> HAL + server link + route -> Agent.
#include <grpcpp/create_channel.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/robot_agent/agent.hpp"
#include "fleetnav/robot_agent/server_link.hpp"
#include "fleetnav/robot_agent/sim_hal.hpp"

int main(int argc, char** argv) {
  std::string robot_id = "lely1";
  std::string kind = "lely-vector";
  std::string sim_address = "127.0.0.1:50061";
  std::string server_address = "127.0.0.1:50051";
  std::string route_path;
  std::vector<double> initial_pose = {0.0, 0.0, 0.0};
  fleetnav::agent::AgentParams params;
  double telemetry_hz = 1.0 / params.telemetry_period_s;
  CLI::App app{"fleetnav-agent: robot daemon (HAL over SimService, telemetry to fleetnavd)"};
  app.add_option("--robot-id", robot_id, "this robot's id")->capture_default_str();
  app.add_option("--kind", kind, "robot kind: lely-vector | mecanum-platform | ackermann-delivery")
      ->capture_default_str();
  app.add_option("--sim", sim_address, "fleetnav-sim address (SimService)")->capture_default_str();
  app.add_option("--server", server_address, "fleetnavd address (AgentService)")
      ->capture_default_str();
  app.add_option("--route", route_path,
                 "route YAML to run once (turn and straight actions); without it the agent "
                 "takes jobs from fleetnavd");
  app.add_option("--max-jobs", params.max_jobs,
                 "in job mode, exit after this many jobs have ended (0 = run until the sim ends)");
  app.add_option("--initial-pose", initial_pose, "pose in the map at start: x_m y_m yaw_deg")
      ->expected(3);
  app.add_option("--telemetry-hz", telemetry_hz, "telemetry rate in robot time (>= 10)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  absl::StatusOr<fleetnav::RobotModel> model = fleetnav::RobotModelByKind(kind);
  if (!model.ok()) {
    spdlog::error("{}", model.status().ToString());
    return 2;
  }
  std::optional<fleetnav::Route> route;
  if (!route_path.empty()) {
    absl::StatusOr<fleetnav::Route> loaded = fleetnav::LoadRoute(route_path);
    if (!loaded.ok()) {
      spdlog::error("{}", loaded.status().ToString());
      return 2;
    }
    route = *loaded;
  }
  params.initial_pose_in_map =
      fleetnav::Pose2(initial_pose[0], initial_pose[1], fleetnav::DegToRad(initial_pose[2]));
  params.telemetry_period_s = telemetry_hz > 0 ? 1.0 / telemetry_hz : 0.0;
  params.exit_when_done = route.has_value();

  // What this agent can execute: a job needs every one of its route's action types here.
  fleetnav::RobotIdentity identity{robot_id, *model, {"straight", "turn"}, "0.1.0"};
  fleetnav::agent::ServerLink link(
      grpc::CreateChannel(server_address, grpc::InsecureChannelCredentials()), identity);
  fleetnav::agent::SimHal hal(grpc::CreateChannel(sim_address, grpc::InsecureChannelCredentials()),
                              robot_id);
  fleetnav::agent::Agent agent(*model, &hal, &link, route, params,
                               route.has_value() ? nullptr : &link);
  spdlog::info("fleetnav-agent '{}' ({}) attached to {}, reporting to {}", robot_id, kind,
               sim_address, server_address);
  absl::StatusOr<fleetnav::agent::AgentResult> result = agent.Run();
  link.Close();
  if (!result.ok()) {
    spdlog::error("fleetnav-agent: {}", result.status().ToString());
    return 1;
  }
  const fleetnav::Pose2& end = result->final_pose_in_map;
  spdlog::info(
      "fleetnav-agent: {} after {} ticks; odometry pose ({:.3f}, {:.3f}, {:.2f} deg); "
      "{} telemetry messages sent",
      !route.has_value() ? std::to_string(result->jobs_finished) + " job(s) ended"
      : result->state == fleetnav::agent::ExecutionState::kSucceeded ? "route succeeded"
      : result->state == fleetnav::agent::ExecutionState::kFailed
          ? "route failed: " + result->failure_reason
          : "stopped",
      result->ticks, end.x_m(), end.y_m(), fleetnav::RadToDeg(end.yaw_rad()), link.sent());
  return result->state == fleetnav::agent::ExecutionState::kFailed ? 1 : 0;
}
