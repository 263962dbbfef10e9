#pragma once

#include <grpcpp/create_channel.h>
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "fleetnav/sim/sim_server.hpp"
#include "fleetnav/v1/sim_service.grpc.pb.h"

namespace fleetnav::testing {

/// A fleetnav-sim serving one world file (from sim/worlds) on a loopback port, and a SimService
/// stub to it. Ticks advance once an agent attaches.
class SimServerFixture : public ::testing::Test {
 protected:
  explicit SimServerFixture(std::string world_file) : world_file_(std::move(world_file)) {}

  void SetUp() override {
    absl::StatusOr<sim::WorldDescription> world =
        sim::LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/" + world_file_);
    ASSERT_TRUE(world.ok()) << world.status();
    sim::SimServerParams params;
    params.listen_address = "127.0.0.1:0";
    params.lockstep.min_attached = 1;
    server_ = std::make_unique<sim::SimServer>(*world, params);
    absl::StatusOr<int> port = server_->Start();
    ASSERT_TRUE(port.ok()) << port.status();
    stub_ = v1::SimService::NewStub(grpc::CreateChannel("127.0.0.1:" + std::to_string(*port),
                                                        grpc::InsecureChannelCredentials()));
  }
  void TearDown() override { server_->Shutdown(); }

  std::string world_file_;
  std::unique_ptr<sim::SimServer> server_;
  std::unique_ptr<v1::SimService::Stub> stub_;
};

}  // namespace fleetnav::testing
