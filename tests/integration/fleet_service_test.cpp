// FleetService over real loopback gRPC against a real SQLite file: every map RPC's success and
// failure paths, with the status code, the field named, and nothing stored on failure.
#include <gmock/gmock.h>
#include <grpcpp/create_channel.h>
#include <gtest/gtest.h>
#include <png.h>

#include <cstring>
#include <filesystem>
#include <limits>

#include "fleetnav/core/map_io.hpp"
#include "fleetnav/proto/map_convert.hpp"
#include "fleetnav/server/rpc/fleet_server.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "test_paths.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

class FleetServiceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    db_path_ = testing::UniqueTempPath("fleet-service") + ".db";
    StartServer();
  }

  void StartServer() {
    server::FleetServerParams params;
    params.listen_address = "127.0.0.1:0";
    params.db_path = db_path_;
    params.max_message_bytes = 4 << 20;
    server_ = std::make_unique<server::FleetServer>(params);
    absl::StatusOr<int> port = server_->Start();
    ASSERT_TRUE(port.ok()) << port.status();
    grpc::ChannelArguments args;
    args.SetMaxSendMessageSize(64 << 20);
    stub_ = v1::FleetService::NewStub(grpc::CreateCustomChannel(
        "127.0.0.1:" + std::to_string(*port), grpc::InsecureChannelCredentials(), args));
  }
  void RestartServer() {
    server_->Shutdown();
    server_.reset();
    StartServer();
  }

  void TearDown() override {
    server_->Shutdown();
    server_.reset();
    std::filesystem::remove(db_path_);
  }

  static v1::OccupancyGrid SmallGrid(int width, int height) {
    absl::StatusOr<OccupancyGrid> grid =
        OccupancyGrid::Filled(width, height, 0.1, Pose2(-1.0, 2.0, 0.25), 0);
    grid->SetValue({1, 1}, 100);
    grid->SetValue({0, 1}, -1);
    return ToProto(*grid);
  }

  grpc::Status Put(const v1::PutMapRequest& request, v1::PutMapResponse* response) {
    grpc::ClientContext context;
    return stub_->PutMap(&context, request, response);
  }

  int MapCount() {
    grpc::ClientContext context;
    v1::ListMapsResponse response;
    EXPECT_TRUE(stub_->ListMaps(&context, {}, &response).ok());
    return response.maps_size();
  }

  std::string db_path_;
  std::unique_ptr<server::FleetServer> server_;
  std::unique_ptr<v1::FleetService::Stub> stub_;
};

TEST_F(FleetServiceTest, PutInlineGridThenGetReturnsItExactlyWithGrowingVersions) {
  v1::PutMapRequest request;
  request.set_map_id("barn");
  *request.mutable_grid() = SmallGrid(4, 3);
  v1::PutMapResponse response;
  ASSERT_TRUE(Put(request, &response).ok());
  EXPECT_EQ(response.version(), 1u);
  ASSERT_TRUE(Put(request, &response).ok());
  EXPECT_EQ(response.version(), 1u);  // the same content is the version that holds it
  request.set_description("second survey");
  ASSERT_TRUE(Put(request, &response).ok());
  EXPECT_EQ(response.version(), 2u);

  grpc::ClientContext context;
  v1::GetMapRequest get;
  get.set_map_id("barn");
  v1::GetMapResponse map;
  ASSERT_TRUE(stub_->GetMap(&context, get, &map).ok());
  EXPECT_EQ(map.info().version(), 2u);
  EXPECT_EQ(map.grid().cells(), request.grid().cells());
  EXPECT_DOUBLE_EQ(map.grid().origin().yaw_rad(), 0.25);
  EXPECT_EQ(map.info().width(), 4u);
  EXPECT_GT(map.info().created_unix_ms(), 1'600'000'000'000);

  grpc::ClientContext context_v1;
  get.set_version(1);
  ASSERT_TRUE(stub_->GetMap(&context_v1, get, &map).ok());
  EXPECT_EQ(map.info().version(), 1u);
}

TEST_F(FleetServiceTest, PutMapServerBytesStoresTheDecodedGrid) {
  absl::StatusOr<OccupancyGrid> grid = FromProto(SmallGrid(5, 4));
  ASSERT_TRUE(grid.ok());
  auto [metadata, image] = GridToMapServer(*grid, "small.pgm");
  v1::PutMapRequest request;
  request.set_map_id("store-1");
  request.mutable_map_server()->set_yaml(MapServerYamlToString(metadata));
  request.mutable_map_server()->set_pgm(EncodePgm(image));
  v1::PutMapResponse response;
  ASSERT_TRUE(Put(request, &response).ok());

  grpc::ClientContext context;
  v1::GetMapRequest get;
  get.set_map_id("store-1");
  v1::GetMapResponse map;
  ASSERT_TRUE(stub_->GetMap(&context, get, &map).ok());
  absl::StatusOr<OccupancyGrid> stored = FromProto(map.grid());
  ASSERT_TRUE(stored.ok());
  EXPECT_EQ(stored->cells(), grid->cells());
}

// A map as ROS users have it: a PNG (RGB, so its greys are averaged) uploaded over gRPC is
// stored as the same grid as its PGM twin; bytes of no image format are refused.
TEST_F(FleetServiceTest, PutMapServerPngStoresTheSameGridAsThePgm) {
  const std::vector<uint8_t> greys = {254, 0, 205, 254, 254, 0};  // 3 x 2, top row first
  std::vector<uint8_t> rgb;
  for (uint8_t v : greys) rgb.insert(rgb.end(), {v, v, v});
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  png.width = 3;
  png.height = 2;
  png.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 1 << 16;
  std::string png_bytes(size, '\0');
  ASSERT_TRUE(png_image_write_to_memory(&png, png_bytes.data(), &size, 0, rgb.data(), 0, nullptr));
  png_bytes.resize(size);
  const std::string yaml = "image: shop.png\nresolution: 0.05\norigin: [1, 2, 0]\n";
  v1::PutMapRequest request;
  request.set_map_id("shop");
  request.mutable_map_server()->set_yaml(yaml);
  request.mutable_map_server()->set_pgm(png_bytes);
  v1::PutMapResponse response;
  ASSERT_TRUE(Put(request, &response).ok());
  grpc::ClientContext context;
  v1::GetMapRequest get;
  get.set_map_id("shop");
  v1::GetMapResponse map;
  ASSERT_TRUE(stub_->GetMap(&context, get, &map).ok());
  PgmImage pgm;
  pgm.width = 3;
  pgm.height = 2;
  pgm.pixels = greys;
  absl::StatusOr<OccupancyGrid> twin = GridFromMapServerBytes(yaml, EncodePgm(pgm));
  ASSERT_TRUE(twin.ok()) << twin.status();
  absl::StatusOr<OccupancyGrid> stored = FromProto(map.grid());
  ASSERT_TRUE(stored.ok());
  EXPECT_EQ(stored->cells(), twin->cells());
  EXPECT_EQ(stored->cells(), (std::vector<int8_t>{0, 0, 100, 0, 100, -1}));

  request.set_map_id("junk");
  request.mutable_map_server()->set_pgm("GIF89a not a map");
  const grpc::Status refused = Put(request, &response);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(refused.error_message(), HasSubstr("not a PGM (P5/P2), PNG or BMP"));
}

TEST_F(FleetServiceTest, BadMapsAreRefusedNamingTheFieldAndNothingIsStored) {
  struct Case {
    std::string name;
    v1::PutMapRequest request;
    std::string field;
  };
  std::vector<Case> cases;
  {
    Case c{"cell count", {}, "cells"};
    c.request.set_map_id("barn");
    *c.request.mutable_grid() = SmallGrid(4, 3);
    c.request.mutable_grid()->set_width(5);
    cases.push_back(c);
  }
  {
    Case c{"nan resolution", {}, "resolution"};
    c.request.set_map_id("barn");
    *c.request.mutable_grid() = SmallGrid(4, 3);
    c.request.mutable_grid()->set_resolution_m(std::numeric_limits<double>::quiet_NaN());
    cases.push_back(c);
  }
  {
    Case c{"negative resolution", {}, "resolution"};
    c.request.set_map_id("barn");
    *c.request.mutable_grid() = SmallGrid(4, 3);
    c.request.mutable_grid()->set_resolution_m(-0.05);
    cases.push_back(c);
  }
  {
    Case c{"too many cells", {}, "exceeds"};
    c.request.set_map_id("barn");
    *c.request.mutable_grid() = SmallGrid(4, 3);
    c.request.mutable_grid()->set_width(20000);
    c.request.mutable_grid()->set_height(20000);
    cases.push_back(c);
  }
  {
    Case c{"infinite origin", {}, "origin"};
    c.request.set_map_id("barn");
    *c.request.mutable_grid() = SmallGrid(4, 3);
    c.request.mutable_grid()->mutable_origin()->set_x_m(std::numeric_limits<double>::infinity());
    cases.push_back(c);
  }
  {
    Case c{"broken pgm", {}, "PGM"};
    c.request.set_map_id("barn");
    c.request.mutable_map_server()->set_yaml(
        "image: x.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
    c.request.mutable_map_server()->set_pgm("P5\n10 10\n255\n\x01\x02");
    cases.push_back(c);
  }
  {
    Case c{"bad map id", {}, "map_id"};
    c.request.set_map_id("Barn/1");
    *c.request.mutable_grid() = SmallGrid(4, 3);
    cases.push_back(c);
  }
  {
    Case c{"no source", {}, "source"};
    c.request.set_map_id("barn");
    cases.push_back(c);
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    v1::PutMapResponse response;
    const grpc::Status status = Put(c.request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_THAT(status.error_message(), HasSubstr(c.field));
  }
  EXPECT_EQ(MapCount(), 0);
}

TEST_F(FleetServiceTest, MessagesOverTheSizeLimitAreRefused) {
  v1::PutMapRequest request;
  request.set_map_id("huge");
  *request.mutable_grid() = SmallGrid(3000, 2000);  // 6 MB of cells > 4 MB limit
  v1::PutMapResponse response;
  EXPECT_EQ(Put(request, &response).error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_EQ(MapCount(), 0);
}

TEST_F(FleetServiceTest, UnknownMapsAndVersionsAreNotFound) {
  grpc::ClientContext context;
  v1::GetMapRequest get;
  get.set_map_id("nowhere");
  v1::GetMapResponse map;
  grpc::Status status = stub_->GetMap(&context, get, &map);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_THAT(status.error_message(), HasSubstr("nowhere"));

  v1::PutMapRequest request;
  request.set_map_id("barn");
  *request.mutable_grid() = SmallGrid(2, 2);
  v1::PutMapResponse response;
  ASSERT_TRUE(Put(request, &response).ok());
  grpc::ClientContext context_version;
  get.set_map_id("barn");
  get.set_version(7);
  EXPECT_EQ(stub_->GetMap(&context_version, get, &map).error_code(), grpc::StatusCode::NOT_FOUND);

  grpc::ClientContext context_delete;
  v1::DeleteMapRequest remove;
  remove.set_map_id("nowhere");
  v1::DeleteMapResponse removed;
  EXPECT_EQ(stub_->DeleteMap(&context_delete, remove, &removed).error_code(),
            grpc::StatusCode::NOT_FOUND);
}

TEST_F(FleetServiceTest, ListAndDeleteMaps) {
  for (const char* id : {"b-map", "a-map"}) {
    v1::PutMapRequest request;
    request.set_map_id(id);
    *request.mutable_grid() = SmallGrid(2, 2);
    v1::PutMapResponse response;
    ASSERT_TRUE(Put(request, &response).ok());
  }
  grpc::ClientContext context;
  v1::ListMapsResponse list;
  ASSERT_TRUE(stub_->ListMaps(&context, {}, &list).ok());
  ASSERT_EQ(list.maps_size(), 2);
  EXPECT_EQ(list.maps(0).map_id(), "a-map");

  grpc::ClientContext context_delete;
  v1::DeleteMapRequest remove;
  remove.set_map_id("a-map");
  v1::DeleteMapResponse removed;
  ASSERT_TRUE(stub_->DeleteMap(&context_delete, remove, &removed).ok());
  EXPECT_EQ(MapCount(), 1);
}

TEST_F(FleetServiceTest, MapsSurviveARestartOfTheServer) {
  v1::PutMapRequest request;
  request.set_map_id("barn");
  *request.mutable_grid() = SmallGrid(3, 3);
  v1::PutMapResponse response;
  ASSERT_TRUE(Put(request, &response).ok());
  RestartServer();
  EXPECT_EQ(MapCount(), 1);
}

}  // namespace
}  // namespace fleetnav
