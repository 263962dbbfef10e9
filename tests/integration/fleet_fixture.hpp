#pragma once

#include <grpcpp/create_channel.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "fleetnav/proto/map_convert.hpp"
#include "fleetnav/proto/route_convert.hpp"
#include "fleetnav/server/rpc/fleet_server.hpp"
#include "fleetnav/sim/world_description.hpp"
#include "fleetnav/sim/world_rasterizer.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "test_paths.hpp"

namespace fleetnav::testing {

/// A fleetnavd on a loopback port with a fresh SQLite file, and a FleetService stub to it.
class FleetServerFixture : public ::testing::Test {
 public:
  /// A route of one straight action on map "barn".
  static Route StraightRoute(const std::string& name, double distance_m) {
    Route route;
    route.name = name;
    route.map_id = "barn";
    route.actions.push_back(RouteAction{StraightAction{distance_m, 0.25}, {}});
    return route;
  }

 protected:
  void SetUp() override {
    db_path_ = UniqueTempPath("fleet") + ".db";
    StartServer();
  }
  void TearDown() override {
    StopServer();
    std::filesystem::remove(db_path_);
  }

  void StartServer() {
    server::FleetServerParams params = Params();
    params.listen_address = "127.0.0.1:0";
    params.db_path = db_path_;
    server_ = std::make_unique<server::FleetServer>(params);
    absl::StatusOr<int> port = server_->Start();
    ASSERT_TRUE(port.ok()) << port.status();
    port_ = *port;
    channel_ = grpc::CreateChannel("127.0.0.1:" + std::to_string(port_),
                                   grpc::InsecureChannelCredentials());
    fleet_ = v1::FleetService::NewStub(channel_);
  }
  void StopServer() {
    if (server_ == nullptr) return;
    server_->Shutdown();
    server_.reset();
  }
  virtual server::FleetServerParams Params() {
    server::FleetServerParams params;
    params.dispatch_period_s = 0.05;
    return params;
  }

  static sim::WorldDescription Barn() {
    absl::StatusOr<sim::WorldDescription> world =
        sim::LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/barn.yaml");
    EXPECT_TRUE(world.ok()) << world.status();
    return *world;
  }

  /// Uploads the barn's generated map (and its markers) as map "barn".
  void PutBarn() {
    const sim::WorldDescription world = Barn();
    absl::StatusOr<OccupancyGrid> grid = sim::RasterizeWorld(world, 0.05);
    ASSERT_TRUE(grid.ok());
    grpc::ClientContext map_context;
    v1::PutMapRequest map;
    map.set_map_id("barn");
    *map.mutable_grid() = ToProto(*grid);
    v1::PutMapResponse map_response;
    ASSERT_TRUE(fleet_->PutMap(&map_context, map, &map_response).ok());
    grpc::ClientContext marker_context;
    v1::PutMarkerSetRequest markers;
    *markers.mutable_marker_set() = ToProto(sim::MarkerSetOf(world, "barn"));
    v1::PutMarkerSetResponse marker_response;
    ASSERT_TRUE(fleet_->PutMarkerSet(&marker_context, markers, &marker_response).ok());
  }

  grpc::Status PutRoute(const Route& route) {
    grpc::ClientContext context;
    v1::PutRouteRequest request;
    *request.mutable_route() = ToProto(route);
    v1::PutRouteResponse response;
    return fleet_->PutRoute(&context, request, &response);
  }

  grpc::Status Submit(const std::string& route, const std::string& key,
                      v1::SubmitJobResponse* response, int priority = 0) {
    grpc::ClientContext context;
    v1::SubmitJobRequest request;
    request.set_route_name(route);
    request.set_idempotency_key(key);
    request.set_priority(priority);
    return fleet_->SubmitJob(&context, request, response);
  }

  std::string db_path_;
  int port_ = 0;
  std::unique_ptr<server::FleetServer> server_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::FleetService::Stub> fleet_;
};

}  // namespace fleetnav::testing
