// fleetnavd --clock sim: timeouts count the simulator's seconds, not the wall's.

#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>

#include "fleetnav/server/rpc/fleet_server.hpp"
#include "fleetnav/sim/sim_server.hpp"
#include "fleetnav/sim/world_description.hpp"
#include "fleetnav/v1/sim_service.grpc.pb.h"
#include "test_paths.hpp"

namespace fleetnav {
namespace {

/// The simulation's calendar at sim time 0: 2023-11-14 22:13:20 UTC.
constexpr int64_t kStartUnixMs = 1'700'000'000'000;

class SimClockTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<sim::WorldDescription> world =
        sim::LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/barn.yaml");
    ASSERT_TRUE(world.ok()) << world.status();
    sim::SimServerParams sim_params;
    sim_params.listen_address = "127.0.0.1:0";
    sim_params.start_unix_ms = kStartUnixMs;
    simulator_ = std::make_unique<sim::SimServer>(*world, sim_params);
    absl::StatusOr<int> port = simulator_->Start();
    ASSERT_TRUE(port.ok()) << port.status();
    sim_address_ = "127.0.0.1:" + std::to_string(*port);
  }

  /// A fleetnavd on the given clock with one robot that sent telemetry once, just now.
  void StartServer(const std::string& sim_clock_address) {
    server::FleetServerParams params;
    params.listen_address = "127.0.0.1:0";
    params.db_path = testing::UniqueTempPath("simclock") + ".db";
    params.registry.stale_after_s = 2.0;
    params.sim_clock_address = sim_clock_address;
    server_ = std::make_unique<server::FleetServer>(params);
    absl::StatusOr<int> port = server_->Start();
    ASSERT_TRUE(port.ok()) << port.status();
    RobotIdentity identity;
    identity.robot_id = "lely1";
    identity.model = LelyVectorModel();
    const uint64_t session = server_->app().registry().Connect(identity);
    ASSERT_TRUE(server_->app().registry().RecordTelemetry("lely1", session, Telemetry{}).ok());
  }

  ConnectionState State() { return server_->app().registry().Get("lely1")->connection; }

  /// 3 s of simulated time (150 ticks of 20 ms), in a fraction of that on the wall, then a few
  /// polls of fleetnavd's feed.
  void StepThreeSimSeconds() {
    auto sim = v1::SimService::NewStub(
        grpc::CreateChannel(sim_address_, grpc::InsecureChannelCredentials()));
    grpc::ClientContext context;
    v1::StepRequest step;
    step.set_ticks(150);
    v1::StepResponse stepped;
    ASSERT_TRUE(sim->Step(&context, step, &stepped).ok());
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }

  std::unique_ptr<sim::SimServer> simulator_;
  std::string sim_address_;
  std::unique_ptr<server::FleetServer> server_;
};

TEST_F(SimClockTest, StaleTimeoutCountsSimulatedSeconds) {
  StartServer(sim_address_);
  // No agent is attached: the lockstep simulator stands still, and so does fleetnavd's time.
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  EXPECT_EQ(State(), ConnectionState::kOnline);
  ASSERT_NO_FATAL_FAILURE(StepThreeSimSeconds());
  EXPECT_EQ(State(), ConnectionState::kStale);
}

TEST_F(SimClockTest, RecordsAreStampedOnTheSimulationsCalendar) {
  StartServer(sim_address_);
  ASSERT_NO_FATAL_FAILURE(StepThreeSimSeconds());
  // Whenever this server started, its calendar is the simulation's: the start plus 3 s.
  EXPECT_EQ(server_->app().clock().UnixMs(), kStartUnixMs + 3'000);
}

TEST_F(SimClockTest, WallClockServerGoesStaleInWallSeconds) {
  StartServer("");
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  EXPECT_EQ(State(), ConnectionState::kStale);
}

TEST_F(SimClockTest, AnUnreachableSimulatorIsRefusedAtStart) {
  server::FleetServerParams params;
  params.listen_address = "127.0.0.1:0";
  params.db_path = testing::UniqueTempPath("simclock") + ".db";
  params.sim_clock_address = "127.0.0.1:1";
  server::FleetServer server(params);
  absl::StatusOr<int> port = server.Start();
  ASSERT_FALSE(port.ok());
  EXPECT_EQ(port.status().code(), absl::StatusCode::kUnavailable);
  EXPECT_NE(port.status().message().find("127.0.0.1:1"), std::string::npos);
}

}  // namespace
}  // namespace fleetnav
