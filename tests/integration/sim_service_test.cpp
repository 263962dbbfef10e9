// SimService over real loopback gRPC: world description, spawning, attach rules, lockstep
// stepping of a real ODE world, and ground truth.
#include <gmock/gmock.h>
#include <grpcpp/create_channel.h>
#include <gtest/gtest.h>

#include "fleetnav/sim/sim_server.hpp"
#include "fleetnav/v1/sim_service.grpc.pb.h"
#include "testing/sim_server_fixture.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;
using AttachStream = grpc::ClientReaderWriter<v1::AttachMessage, v1::SensorFrame>;

class SimServiceTest : public testing::SimServerFixture {
 protected:
  SimServiceTest() : SimServerFixture("barn.yaml") {}

  static v1::AttachMessage AttachTo(const std::string& robot_id) {
    v1::AttachMessage message;
    message.mutable_attach()->set_robot_id(robot_id);
    return message;
  }

  static v1::AttachMessage Forward(uint64_t tick, double speed_mps) {
    v1::AttachMessage message;
    message.mutable_command()->set_tick(tick);
    message.mutable_command()->mutable_twist()->set_vx_mps(speed_mps);
    return message;
  }
};

TEST_F(SimServiceTest, GetWorldDescribesTheBarnAndItsRobot) {
  grpc::ClientContext context;
  v1::GetWorldResponse world;
  ASSERT_TRUE(stub_->GetWorld(&context, {}, &world).ok());
  EXPECT_EQ(world.world_name(), "barn");
  EXPECT_NEAR(world.width_m(), 26.0, 1e-9);
  ASSERT_EQ(world.robots_size(), 1);
  EXPECT_EQ(world.robots(0).robot_id(), "lely1");
  EXPECT_EQ(world.robots(0).model().kinematics(), v1::KINEMATICS_DIFFERENTIAL);
  EXPECT_NEAR(world.control_period_s(), 0.02, 1e-12);
}

TEST_F(SimServiceTest, AttachedAgentDrivesTheRobotInLockstep) {
  grpc::ClientContext context;
  std::unique_ptr<AttachStream> stream = stub_->Attach(&context);
  ASSERT_TRUE(stream->Write(AttachTo("lely1")));
  v1::SensorFrame frame;
  uint64_t expected_tick = 0;
  for (int i = 0; i < 250; ++i) {  // 5 s at 0.2 m/s
    ASSERT_TRUE(stream->Read(&frame));
    if (i == 0) expected_tick = frame.tick();
    EXPECT_EQ(frame.tick(), expected_tick + i);  // one frame per tick, none skipped
    EXPECT_EQ(frame.encoders_size(), 2);
    ASSERT_TRUE(stream->Write(Forward(frame.tick(), 0.2)));
  }
  grpc::ClientContext truth_context;
  v1::GroundTruth truth;
  ASSERT_TRUE(stub_->GetGroundTruth(&truth_context, {}, &truth).ok());
  ASSERT_EQ(truth.robots_size(), 1);
  // Started at (-5.5, 0) heading +x; about 1 m in 5 s, less the acceleration phase.
  EXPECT_NEAR(truth.robots(0).pose().x_m(), -5.5 + 1.0, 0.1);
  EXPECT_NEAR(truth.robots(0).pose().y_m(), 0.0, 0.02);
  EXPECT_GT(truth.robots(0).up_z(), 0.95);
  stream->WritesDone();
  v1::SensorFrame unread;
  while (stream->Read(&unread)) {
  }
  EXPECT_TRUE(stream->Finish().ok());
}

TEST_F(SimServiceTest, AttachToUnknownRobotIsNotFound) {
  grpc::ClientContext context;
  std::unique_ptr<AttachStream> stream = stub_->Attach(&context);
  ASSERT_TRUE(stream->Write(AttachTo("ghost")));
  stream->WritesDone();
  const grpc::Status status = stream->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_THAT(status.error_message(), HasSubstr("ghost"));
}

TEST_F(SimServiceTest, SecondAttachToTheSameRobotIsRefused) {
  grpc::ClientContext first_context;
  std::unique_ptr<AttachStream> first = stub_->Attach(&first_context);
  ASSERT_TRUE(first->Write(AttachTo("lely1")));
  v1::SensorFrame frame;
  ASSERT_TRUE(first->Read(&frame));

  grpc::ClientContext second_context;
  std::unique_ptr<AttachStream> second = stub_->Attach(&second_context);
  ASSERT_TRUE(second->Write(AttachTo("lely1")));
  second->WritesDone();
  const grpc::Status status = second->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);

  ASSERT_TRUE(first->Write(Forward(frame.tick(), 0.0)));
  first->WritesDone();
  while (first->Read(&frame)) {
  }
  EXPECT_TRUE(first->Finish().ok());
}

TEST_F(SimServiceTest, CommandForTheWrongTickIsInvalidArgument) {
  grpc::ClientContext context;
  std::unique_ptr<AttachStream> stream = stub_->Attach(&context);
  ASSERT_TRUE(stream->Write(AttachTo("lely1")));
  v1::SensorFrame frame;
  ASSERT_TRUE(stream->Read(&frame));
  ASSERT_TRUE(stream->Write(Forward(frame.tick() + 5, 0.1)));
  stream->WritesDone();
  while (stream->Read(&frame)) {
  }
  const grpc::Status status = stream->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("tick"));
}

TEST_F(SimServiceTest, SpawnAddsRobotsAndRefusesBadOnes) {
  grpc::ClientContext context;
  v1::SpawnRequest request;
  request.set_robot_id("lely2");
  request.set_kind_name("lely-vector");
  request.mutable_pose()->set_x_m(5.0);
  v1::SpawnResponse response;
  ASSERT_TRUE(stub_->Spawn(&context, request, &response).ok());

  grpc::ClientContext duplicate_context;
  EXPECT_EQ(stub_->Spawn(&duplicate_context, request, &response).error_code(),
            grpc::StatusCode::ALREADY_EXISTS);

  grpc::ClientContext kind_context;
  request.set_robot_id("robot3");
  request.set_kind_name("hovercraft");
  EXPECT_EQ(stub_->Spawn(&kind_context, request, &response).error_code(),
            grpc::StatusCode::NOT_FOUND);

  grpc::ClientContext world_context;
  v1::GetWorldResponse world;
  ASSERT_TRUE(stub_->GetWorld(&world_context, {}, &world).ok());
  EXPECT_EQ(world.robots_size(), 2);
}

TEST_F(SimServiceTest, StepAdvancesWithoutAgents) {
  grpc::ClientContext context;
  v1::StepRequest request;
  request.set_ticks(10);
  v1::StepResponse response;
  ASSERT_TRUE(stub_->Step(&context, request, &response).ok());
  EXPECT_EQ(response.tick(), 10u);
  EXPECT_EQ(response.sim_time_ns(), 200'000'000);
}

}  // namespace
}  // namespace fleetnav
