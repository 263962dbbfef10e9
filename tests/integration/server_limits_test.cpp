// fleetnavd's input limits over real loopback gRPC: a request beyond a limit is refused with
// RESOURCE_EXHAUSTED naming the limit and nothing of it is kept; a huge id is answered with the
// right code and a message that repeats at most 128 bytes of it.
#include <gmock/gmock.h>

#include <memory>
#include <string>

#include "fleet_fixture.hpp"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/v1/agent_service.grpc.pb.h"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

class ServerLimitsTest : public testing::FleetServerFixture {
 protected:
  server::FleetServerParams Params() override {
    server::FleetServerParams params = FleetServerFixture::Params();
    params.limits.max_markers = 50;
    params.limits.max_route_actions = 20;
    params.limits.max_waypoints_per_action = 5;
    params.limits.max_map_cells = 1'000'000;
    params.limits.max_capabilities = 8;
    params.limits.max_footprint_points = 8;
    return params;
  }
};

void ExpectLimit(const grpc::Status& status, const std::string& limit) {
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
  EXPECT_THAT(status.error_message(), HasSubstr("limits." + limit));
}

TEST_F(ServerLimitsTest, AMarkerSetOverTheLimitIsRefusedAndNotStored) {
  PutBarn();  // the barn's own markers fit
  MarkerSet markers;
  markers.map_id = "barn";
  for (int i = 1; i <= 51; ++i) {
    StripeMarker marker;
    marker.id = i;
    marker.position_m = Eigen::Vector2d(0.1 * i, 0.0);
    markers.markers.push_back(marker);
  }
  grpc::ClientContext context;
  v1::PutMarkerSetRequest request;
  *request.mutable_marker_set() = ToProto(markers);
  v1::PutMarkerSetResponse response;
  ExpectLimit(fleet_->PutMarkerSet(&context, request, &response), "max_markers");
  grpc::ClientContext get_context;
  v1::GetMarkerSetRequest get;
  get.set_map_id("barn");
  v1::GetMarkerSetResponse stored;
  ASSERT_TRUE(fleet_->GetMarkerSet(&get_context, get, &stored).ok());
  EXPECT_EQ(stored.version(), 1u);  // still the barn's set
}

TEST_F(ServerLimitsTest, RoutesOverTheActionOrWaypointLimitAreRefusedAndNotStored) {
  PutBarn();
  Route long_route = StraightRoute("long", 1.0);
  long_route.actions.resize(21, long_route.actions.front());
  ExpectLimit(PutRoute(long_route), "max_route_actions");

  Route winding = StraightRoute("winding", 1.0);
  FreeNavigationAction nav;
  nav.goal = Pose2(0.0, 0.0, 0.0);
  nav.waypoints_m.assign(6, Eigen::Vector2d(0.0, 0.0));
  winding.actions = {RouteAction{nav, {EndConditionKind::kGoalReached}}};
  ExpectLimit(PutRoute(winding), "max_waypoints_per_action");

  grpc::ClientContext context;
  v1::ListRoutesRequest list;
  v1::ListRoutesResponse routes;
  ASSERT_TRUE(fleet_->ListRoutes(&context, list, &routes).ok());
  EXPECT_EQ(routes.routes_size(), 0);
}

TEST_F(ServerLimitsTest, AMapOverTheCellLimitIsRefusedAndNotStored) {
  absl::StatusOr<OccupancyGrid> grid =
      OccupancyGrid::Create(1001, 1000, 0.05, Pose2(), std::vector<int8_t>(1001 * 1000, 0));
  ASSERT_TRUE(grid.ok());
  grpc::ClientContext context;
  v1::PutMapRequest request;
  request.set_map_id("big");
  *request.mutable_grid() = ToProto(*grid);
  v1::PutMapResponse response;
  ExpectLimit(fleet_->PutMap(&context, request, &response), "max_map_cells");
  grpc::ClientContext list_context;
  v1::ListMapsResponse maps;
  ASSERT_TRUE(fleet_->ListMaps(&list_context, v1::ListMapsRequest(), &maps).ok());
  EXPECT_EQ(maps.maps_size(), 0);
}

/// Sends `hello` on a new agent stream and returns how the server ended it.
grpc::Status HelloStatus(const std::shared_ptr<grpc::Channel>& channel,
                         const RobotIdentity& identity) {
  auto agents = v1::AgentService::NewStub(channel);
  grpc::ClientContext context;
  auto stream = agents->Connect(&context);
  v1::AgentMessage hello;
  *hello.mutable_hello() = ToProto(identity);
  stream->Write(hello);
  v1::ServerMessage message;
  while (stream->Read(&message)) {
    if (message.has_welcome()) {
      stream->WritesDone();
      context.TryCancel();
    }
  }
  return stream->Finish();
}

TEST_F(ServerLimitsTest, AHelloOverTheCapabilityOrFootprintLimitIsRefusedAndNotKept) {
  RobotIdentity many_capabilities{"ra", LelyVectorModel(), {}, "t"};
  for (int i = 0; i < 9; ++i) many_capabilities.capabilities.push_back("c" + std::to_string(i));
  ExpectLimit(HelloStatus(channel_, many_capabilities), "max_capabilities");

  RobotIdentity big_footprint{"rb", LelyVectorModel(), {"straight"}, "t"};
  big_footprint.model.footprint_m.clear();
  for (int i = 0; i < 9; ++i) {
    const double angle = 2.0 * kPi * i / 9.0;
    big_footprint.model.footprint_m.emplace_back(std::cos(angle), std::sin(angle));
  }
  ExpectLimit(HelloStatus(channel_, big_footprint), "max_footprint_points");

  grpc::ClientContext context;
  v1::ListRobotsResponse robots;
  ASSERT_TRUE(fleet_->ListRobots(&context, v1::ListRobotsRequest(), &robots).ok());
  EXPECT_EQ(robots.robots_size(), 0);
}

TEST_F(ServerLimitsTest, AHugeIdGetsTheRightCodeAndAShortMessage) {
  const std::string huge(100'000, 'j');
  {
    grpc::ClientContext context;
    v1::GetJobRequest request;
    request.set_job_id(huge);
    v1::GetJobResponse response;
    const grpc::Status status = fleet_->GetJob(&context, request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND) << status.error_message().size();
    EXPECT_LT(status.error_message().size(), 200u);
    EXPECT_THAT(status.error_message(), HasSubstr("100000 bytes"));
  }
  {
    grpc::ClientContext context;
    v1::GetRobotRequest request;
    request.set_robot_id(huge);
    v1::GetRobotResponse response;
    const grpc::Status status = fleet_->GetRobot(&context, request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND) << status.error_message().size();
    EXPECT_LT(status.error_message().size(), 200u);
  }
  {
    grpc::ClientContext context;
    v1::GetRouteRequest request;
    request.set_name(huge);
    v1::GetRouteResponse response;
    const grpc::Status status = fleet_->GetRoute(&context, request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_LT(status.error_message().size(), 200u);
  }
  {
    grpc::ClientContext context;
    v1::GetMapRequest request;
    request.set_map_id(huge);
    v1::GetMapResponse response;
    const grpc::Status status = fleet_->GetMap(&context, request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_LT(status.error_message().size(), 200u);
  }
  RobotIdentity huge_id{huge, LelyVectorModel(), {"straight"}, "t"};
  const grpc::Status hello = HelloStatus(channel_, huge_id);
  EXPECT_EQ(hello.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_LT(hello.error_message().size(), 200u);
}

}  // namespace
}  // namespace fleetnav
