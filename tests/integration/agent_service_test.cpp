// AgentService and the fleet views over real loopback gRPC: registration, telemetry ingest,
// bad streams, the replace-on-reconnect rule, and WatchFleet's snapshot-then-updates.
#include <gmock/gmock.h>
#include <grpcpp/create_channel.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>

#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/server/rpc/fleet_server.hpp"
#include "fleetnav/v1/agent_service.grpc.pb.h"
#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "test_paths.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;
using AgentStream = grpc::ClientReaderWriter<v1::AgentMessage, v1::ServerMessage>;

class AgentServiceTest : public ::testing::Test {
 protected:
  void SetUp() override { StartServer(/*stale_after_s=*/2.0); }

  void StartServer(double stale_after_s) {
    if (server_ != nullptr) {
      server_->Shutdown();
      server_.reset();
    }
    db_path_ = testing::UniqueTempPath("agent-service") + ".db";
    server::FleetServerParams params;
    params.listen_address = "127.0.0.1:0";
    params.db_path = db_path_;
    params.registry.stale_after_s = stale_after_s;
    server_ = std::make_unique<server::FleetServer>(params);
    absl::StatusOr<int> port = server_->Start();
    ASSERT_TRUE(port.ok()) << port.status();
    auto channel = grpc::CreateChannel("127.0.0.1:" + std::to_string(*port),
                                       grpc::InsecureChannelCredentials());
    agents_ = v1::AgentService::NewStub(channel);
    fleet_ = v1::FleetService::NewStub(channel);
  }
  void TearDown() override {
    server_->Shutdown();
    server_.reset();
    std::filesystem::remove(db_path_);
  }

  static v1::AgentMessage Hello(const std::string& robot_id) {
    v1::AgentMessage message;
    *message.mutable_hello() = ToProto(RobotIdentity{robot_id, LelyVectorModel(), {}, "test"});
    return message;
  }

  static v1::AgentMessage TelemetryAt(double x_m, int64_t stamp_ns) {
    Telemetry telemetry;
    telemetry.stamp_ns = stamp_ns;
    telemetry.pose_in_map = Pose2(x_m, 1.0, 0.5);
    v1::AgentMessage message;
    *message.mutable_telemetry() = ToProto(telemetry);
    return message;
  }

  /// Opens an agent stream, says hello as `robot_id` and reads the welcome.
  std::unique_ptr<AgentStream> ConnectAs(const std::string& robot_id,
                                         grpc::ClientContext* context) {
    std::unique_ptr<AgentStream> stream = agents_->Connect(context);
    v1::ServerMessage welcome;
    EXPECT_TRUE(stream->Write(Hello(robot_id)));
    EXPECT_TRUE(stream->Read(&welcome) && welcome.has_welcome());
    return stream;
  }

  /// Waits (bounded) until the server's registry satisfies `done`.
  template <typename Predicate>
  bool Eventually(Predicate done) {
    for (int i = 0; i < 200; ++i) {
      if (done()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }

  std::string db_path_;
  std::unique_ptr<server::FleetServer> server_;
  std::unique_ptr<v1::AgentService::Stub> agents_;
  std::unique_ptr<v1::FleetService::Stub> fleet_;
};

TEST_F(AgentServiceTest, HelloThenTelemetryIsVisibleThroughFleetService) {
  grpc::ClientContext context;
  std::unique_ptr<AgentStream> stream = ConnectAs("lely1", &context);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(stream->Write(TelemetryAt(i * 0.1, i * 100'000'000)));

  ASSERT_TRUE(Eventually([&] {
    auto record = server_->app().registry().Get("lely1");
    return record.ok() && record->telemetry_count == 5;
  }));
  grpc::ClientContext get_context;
  v1::GetRobotRequest request;
  request.set_robot_id("lely1");
  v1::GetRobotResponse robot;
  ASSERT_TRUE(fleet_->GetRobot(&get_context, request, &robot).ok());
  EXPECT_EQ(robot.robot().connection(), v1::CONNECTION_STATE_ONLINE);
  EXPECT_EQ(robot.robot().kind_name(), "lely-vector");
  EXPECT_NEAR(robot.robot().last_telemetry().pose_in_map().pose().x_m(), 0.4, 1e-12);

  stream->WritesDone();
  EXPECT_TRUE(stream->Finish().ok());
  EXPECT_TRUE(Eventually([&] {
    return server_->app().registry().Get("lely1")->connection == ConnectionState::kOffline;
  }));
}

TEST_F(AgentServiceTest, FirstMessageMustBeHello) {
  grpc::ClientContext context;
  std::unique_ptr<AgentStream> stream = agents_->Connect(&context);
  ASSERT_TRUE(stream->Write(TelemetryAt(0, 0)));
  stream->WritesDone();
  const grpc::Status status = stream->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("hello"));
  EXPECT_TRUE(server_->app().registry().Snapshot().empty());
}

TEST_F(AgentServiceTest, BadRobotIdIsRefusedAndNotRegistered) {
  grpc::ClientContext context;
  std::unique_ptr<AgentStream> stream = agents_->Connect(&context);
  ASSERT_TRUE(stream->Write(Hello("no spaces allowed")));
  stream->WritesDone();
  const grpc::Status status = stream->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("robot_id"));
  EXPECT_TRUE(server_->app().registry().Snapshot().empty());
}

TEST_F(AgentServiceTest, NonFiniteTelemetryEndsTheStreamAndIsNotStored) {
  grpc::ClientContext context;
  std::unique_ptr<AgentStream> stream = agents_->Connect(&context);
  ASSERT_TRUE(stream->Write(Hello("lely1")));
  stream->Write(TelemetryAt(std::numeric_limits<double>::quiet_NaN(), 0));
  stream->WritesDone();
  v1::ServerMessage ignored;
  while (stream->Read(&ignored)) {
  }
  const grpc::Status status = stream->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("pose_in_map"));
  EXPECT_EQ(server_->app().registry().Get("lely1")->telemetry_count, 0u);
}

TEST_F(AgentServiceTest, SecondConnectionWithSameIdReplacesTheFirst) {
  grpc::ClientContext first_context;
  std::unique_ptr<AgentStream> first = ConnectAs("lely1", &first_context);

  grpc::ClientContext second_context;
  std::unique_ptr<AgentStream> second = ConnectAs("lely1", &second_context);

  // The replaced stream's next telemetry ends it with FailedPrecondition.
  first->Write(TelemetryAt(1.0, 1));
  first->WritesDone();
  v1::ServerMessage ignored;
  while (first->Read(&ignored)) {
  }
  const grpc::Status first_status = first->Finish();
  EXPECT_EQ(first_status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(first_status.error_message(), HasSubstr("replaced"));

  // The replacement keeps working and the robot stays online.
  ASSERT_TRUE(second->Write(TelemetryAt(2.0, 2)));
  ASSERT_TRUE(
      Eventually([&] { return server_->app().registry().Get("lely1")->telemetry_count == 1; }));
  EXPECT_EQ(server_->app().registry().Get("lely1")->connection, ConnectionState::kOnline);
  EXPECT_NEAR(server_->app().registry().Get("lely1")->last_telemetry->pose_in_map.x_m(), 2.0,
              1e-12);
  second->WritesDone();
  EXPECT_TRUE(second->Finish().ok());
}

// A replaced stream cannot end the robot's job either: its event is refused like its telemetry
// (before, an event went straight through and a job could be marked failed from the old stream).
TEST_F(AgentServiceTest, ReplacedStreamsEventIsRefused) {
  grpc::ClientContext first_context;
  std::unique_ptr<AgentStream> first = ConnectAs("lely1", &first_context);
  grpc::ClientContext second_context;
  std::unique_ptr<AgentStream> second = ConnectAs("lely1", &second_context);

  v1::AgentMessage event;
  event.mutable_event()->set_type(v1::AgentEvent::TYPE_JOB_FAILED);
  event.mutable_event()->set_job_id("job-of-lely1");
  event.mutable_event()->set_reason("sent on the old stream");
  first->Write(event);
  first->WritesDone();
  v1::ServerMessage ignored;
  while (first->Read(&ignored)) {
  }
  const grpc::Status first_status = first->Finish();
  EXPECT_EQ(first_status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(first_status.error_message(), HasSubstr("replaced"));
  EXPECT_EQ(server_->app().registry().Get("lely1")->connection, ConnectionState::kOnline);
  second->WritesDone();
  EXPECT_TRUE(second->Finish().ok());
}

TEST_F(AgentServiceTest, WatchFleetStartsWithSnapshotThenSendsUpdates) {
  grpc::ClientContext agent_context;
  std::unique_ptr<AgentStream> agent = ConnectAs("lely1", &agent_context);

  grpc::ClientContext watch_context;
  v1::WatchFleetRequest request;
  request.set_rate_hz(50);
  auto watch = fleet_->WatchFleet(&watch_context, request);
  v1::FleetUpdate update;
  ASSERT_TRUE(watch->Read(&update));
  EXPECT_TRUE(update.snapshot());
  ASSERT_EQ(update.robots_size(), 1);
  EXPECT_EQ(update.robots(0).robot_id(), "lely1");

  ASSERT_TRUE(agent->Write(TelemetryAt(3.0, 5)));
  bool saw_pose = false;
  for (int i = 0; i < 50 && !saw_pose; ++i) {
    ASSERT_TRUE(watch->Read(&update));
    EXPECT_FALSE(update.snapshot());
    for (const auto& robot : update.robots()) {
      saw_pose |= std::abs(robot.last_telemetry().pose_in_map().pose().x_m() - 3.0) < 1e-12;
    }
  }
  EXPECT_TRUE(saw_pose);
  watch_context.TryCancel();
  (void)watch->Finish();
  agent->WritesDone();
  (void)agent->Finish();
}

TEST_F(AgentServiceTest, WatchFleetReportsARobotThatFallsSilentAsStale) {
  StartServer(/*stale_after_s=*/0.2);
  grpc::ClientContext agent_context;
  std::unique_ptr<AgentStream> agent = ConnectAs("lely1", &agent_context);

  grpc::ClientContext watch_context;
  v1::WatchFleetRequest request;
  request.set_rate_hz(20);
  auto watch = fleet_->WatchFleet(&watch_context, request);
  v1::FleetUpdate update;
  ASSERT_TRUE(watch->Read(&update));
  ASSERT_EQ(update.robots_size(), 1);
  EXPECT_EQ(update.robots(0).connection(), v1::CONNECTION_STATE_ONLINE);
  bool saw_stale = false;
  for (int i = 0; i < 40 && !saw_stale; ++i) {  // the robot says nothing after its hello
    ASSERT_TRUE(watch->Read(&update));
    for (const auto& robot : update.robots()) {
      saw_stale |= robot.connection() == v1::CONNECTION_STATE_STALE;
    }
  }
  EXPECT_TRUE(saw_stale);
  watch_context.TryCancel();
  (void)watch->Finish();
  agent->WritesDone();
  (void)agent->Finish();
}

TEST_F(AgentServiceTest, WatchFleetRefusesABadRate) {
  grpc::ClientContext context;
  v1::WatchFleetRequest request;
  request.set_rate_hz(-1);
  auto watch = fleet_->WatchFleet(&context, request);
  v1::FleetUpdate update;
  EXPECT_FALSE(watch->Read(&update));
  const grpc::Status status = watch->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("rate_hz"));
}

TEST_F(AgentServiceTest, UnknownRobotIsNotFound) {
  grpc::ClientContext context;
  v1::GetRobotRequest request;
  request.set_robot_id("ghost");
  v1::GetRobotResponse response;
  const grpc::Status status = fleet_->GetRobot(&context, request, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_THAT(status.error_message(), HasSubstr("ghost"));
}

}  // namespace
}  // namespace fleetnav

namespace fleetnav {
namespace {

TEST_F(AgentServiceTest, TelemetryIsDownSampledIntoThePoseHistory) {
  grpc::ClientContext context;
  std::unique_ptr<AgentStream> stream = ConnectAs("lely1", &context);
  // 2.5 s of telemetry at 20 Hz: the recorder keeps about one sample per second.
  for (int i = 0; i < 50; ++i) {
    ASSERT_TRUE(stream->Write(TelemetryAt(0.01 * i, int64_t{50'000'000} * i)));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  absl::StatusOr<std::vector<storage::PoseSample>> history =
      server_->app().pose_history().ListPoses("lely1", 0, 1000);
  ASSERT_TRUE(history.ok()) << history.status();
  EXPECT_GE(history->size(), 1u);
  EXPECT_LE(history->size(), 4u);
  for (const storage::PoseSample& sample : *history) {
    EXPECT_NEAR(sample.pose_in_map.y_m(), 1.0, 1e-12);
  }
  stream->WritesDone();
  (void)stream->Finish();
}

}  // namespace
}  // namespace fleetnav

namespace fleetnav {
namespace {

TEST_F(AgentServiceTest, ConnectedRobotsAreToldOfNewMapAndMarkerVersions) {
  grpc::ClientContext context;
  std::unique_ptr<AgentStream> stream = ConnectAs("lely1", &context);
  v1::ServerMessage message;

  grpc::ClientContext put_context;
  v1::PutMapRequest put;
  put.set_map_id("barn");
  put.mutable_grid()->set_width(4);
  put.mutable_grid()->set_height(4);
  put.mutable_grid()->set_resolution_m(0.5);
  put.mutable_grid()->set_cells(std::string(16, '\0'));
  v1::PutMapResponse response;
  ASSERT_TRUE(fleet_->PutMap(&put_context, put, &response).ok());
  ASSERT_TRUE(stream->Read(&message));
  ASSERT_TRUE(message.has_map_update());
  EXPECT_EQ(message.map_update().map_id(), "barn");
  EXPECT_EQ(message.map_update().map_version(), 1u);
  EXPECT_EQ(message.map_update().marker_set_version(), 0u);

  grpc::ClientContext markers_context;
  v1::PutMarkerSetRequest markers;
  markers.mutable_marker_set()->set_map_id("barn");
  v1::StripeMarker* marker = markers.mutable_marker_set()->add_markers();
  marker->set_id(1);
  marker->mutable_pose()->set_x_m(1.0);
  marker->set_length_m(0.5);
  v1::PutMarkerSetResponse markers_response;
  ASSERT_TRUE(fleet_->PutMarkerSet(&markers_context, markers, &markers_response).ok());
  ASSERT_TRUE(stream->Read(&message));
  ASSERT_TRUE(message.has_map_update());
  EXPECT_EQ(message.map_update().marker_set_version(), 1u);
  stream->WritesDone();
  (void)stream->Finish();
}

}  // namespace
}  // namespace fleetnav
