// The walking skeleton end to end: fleetnavd, fleetnav-sim and one agent in one test binary,
// talking real gRPC over loopback on ephemeral ports, with a real SQLite file and real ODE.
#include <grpcpp/create_channel.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/localization/dead_reckoning_localizer.hpp"
#include "fleetnav/robot_agent/agent.hpp"
#include "fleetnav/robot_agent/server_link.hpp"
#include "fleetnav/robot_agent/sim_hal.hpp"
#include "fleetnav/server/rpc/fleet_server.hpp"
#include "fleetnav/sim/sim_server.hpp"
#include "test_paths.hpp"

namespace fleetnav {
namespace {

std::shared_ptr<grpc::Channel> Loopback(int port) {
  return grpc::CreateChannel("127.0.0.1:" + std::to_string(port),
                             grpc::InsecureChannelCredentials());
}

TEST(WalkingSkeletonTest, DemoRouteReachesNominalEndAndServerGetsTelemetryAtTenHertz) {
  const std::string db_path = testing::UniqueTempPath("skeleton") + ".db";
  server::FleetServerParams server_params;
  server_params.listen_address = "127.0.0.1:0";
  server_params.db_path = db_path;
  server::FleetServer fleet(server_params);
  absl::StatusOr<int> fleet_port = fleet.Start();
  ASSERT_TRUE(fleet_port.ok()) << fleet_port.status();

  absl::StatusOr<sim::WorldDescription> world =
      sim::LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/barn.yaml");
  ASSERT_TRUE(world.ok()) << world.status();
  ASSERT_EQ(world->robots.size(), 1u);
  const Pose2 start = world->robots[0].pose;
  sim::SimServerParams sim_params;
  sim_params.listen_address = "127.0.0.1:0";
  sim_params.simulation.seed = 11;
  sim::SimServer simulator(*world, sim_params);
  absl::StatusOr<int> sim_port = simulator.Start();
  ASSERT_TRUE(sim_port.ok()) << sim_port.status();

  absl::StatusOr<Route> route = LoadRoute(std::string(FLEETNAV_ROUTES_DIR) + "/demo.yaml");
  ASSERT_TRUE(route.ok()) << route.status();
  const RobotModel model = LelyVectorModel();
  agent::AgentResult result;
  {
    agent::ServerLink link(Loopback(*fleet_port), RobotIdentity{"lely1", model, {}, "test"});
    agent::SimHal hal(Loopback(*sim_port), "lely1");
    localization::DeadReckoningLocalizer localizer =
        localization::DeadReckoningLocalizer::Create(model, start).value();
    agent::Agent agent(agent::RouteContext{model, std::nullopt, nullptr},
                       agent::AgentPorts{&hal, &localizer, &link, nullptr}, *route,
                       agent::AgentParams{});
    absl::StatusOr<agent::AgentResult> run = agent.Run();
    ASSERT_TRUE(run.ok()) << run.status();
    result = *run;
    link.Close();
    EXPECT_EQ(link.dropped(), 0u);
  }
  ASSERT_EQ(result.state, agent::ExecutionState::kSucceeded) << result.failure_reason;

  // Ground truth within 0.2 m and 3° of the route's nominal end: (x0 + 5, y0 + 3, +90°).
  const Pose2 nominal_end = start * Pose2(5.0, 3.0, kPi / 2);
  const sim::GroundTruthSnapshot truth = simulator.lockstep().GroundTruth();
  ASSERT_EQ(truth.robots.size(), 1u);
  const Pose2& true_end = truth.robots[0].pose;
  EXPECT_LT((true_end.translation() - nominal_end.translation()).norm(), 0.2);
  EXPECT_LT(std::abs(AngleDifference(true_end.yaw_rad(), nominal_end.yaw_rad())), DegToRad(3.0));
  EXPECT_GT(truth.robots[0].up_z, 0.95);
  EXPECT_TRUE(truth.contacts.empty());

  // The server holds the robot's telemetry at ≥ 10 Hz of sim time, ending near the truth.
  absl::StatusOr<RobotRecord> record = fleet.app().registry().Get("lely1");
  ASSERT_TRUE(record.ok()) << record.status();
  ASSERT_TRUE(record->last_telemetry.has_value());
  const double last_stamp_s = record->last_telemetry->stamp_ns * 1e-9;
  ASSERT_GT(last_stamp_s, 30.0);  // the route takes about 40 s of sim time
  const double rate_hz = (record->telemetry_count - 1) / last_stamp_s;
  EXPECT_GE(rate_hz, 10.0);
  EXPECT_EQ(record->telemetry_count, result.telemetry_sent);
  // The agent hung up at the end. The server marks it offline once its side of the stream has
  // finished, which may come a moment after the agent saw the call end.
  absl::StatusOr<RobotRecord> after = record;
  for (int i = 0; i < 50 && after.ok() && after->connection != ConnectionState::kOffline; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    after = fleet.app().registry().Get("lely1");
  }
  ASSERT_TRUE(after.ok()) << after.status();
  EXPECT_EQ(after->connection, ConnectionState::kOffline);
  EXPECT_LT((record->last_telemetry->pose_in_map.translation() - true_end.translation()).norm(),
            0.05);

  simulator.Shutdown();
  fleet.Shutdown();
  std::filesystem::remove(db_path);
}

}  // namespace
}  // namespace fleetnav
