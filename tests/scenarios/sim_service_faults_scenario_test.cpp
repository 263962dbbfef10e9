// SimService's Reset and InjectFault over loopback gRPC: argument errors, a fault's effect on
// the next frames, and a reset that starts the run over.
#include <grpcpp/create_channel.h>
#include <gtest/gtest.h>

#include "fleetnav/sim/sim_server.hpp"
#include "fleetnav/v1/sim_service.grpc.pb.h"
#include "testing/sim_server_fixture.hpp"

namespace fleetnav {
namespace {

class SimServiceFaultsTest : public testing::SimServerFixture {
 protected:
  SimServiceFaultsTest() : SimServerFixture("supermarket.yaml") {}

  grpc::Status Inject(const v1::InjectFaultRequest& request) {
    grpc::ClientContext context;
    v1::InjectFaultResponse response;
    return stub_->InjectFault(&context, request, &response);
  }
  v1::GroundTruth Truth() {
    grpc::ClientContext context;
    v1::GroundTruth truth;
    EXPECT_TRUE(stub_->GetGroundTruth(&context, v1::GetGroundTruthRequest{}, &truth).ok());
    return truth;
  }
  void Step(uint32_t ticks) {
    grpc::ClientContext context;
    v1::StepRequest request;
    request.set_ticks(ticks);
    v1::StepResponse response;
    ASSERT_TRUE(stub_->Step(&context, request, &response).ok());
  }
};

TEST_F(SimServiceFaultsTest, InjectFaultAnswersClearErrors) {
  v1::InjectFaultRequest unspecified;
  grpc::Status status = Inject(unspecified);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("type"), std::string::npos);

  v1::InjectFaultRequest no_region;
  no_region.set_type(v1::FAULT_TYPE_REMOVE_FENCE_SEGMENT);
  status = Inject(no_region);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("region"), std::string::npos);

  v1::InjectFaultRequest ghost;
  ghost.set_type(v1::FAULT_TYPE_SLOW_DOWN);
  ghost.set_robot_id("ghost");
  ghost.set_factor(0.5);
  EXPECT_EQ(Inject(ghost).error_code(), grpc::StatusCode::NOT_FOUND);

  v1::InjectFaultRequest sensor;
  sensor.set_type(v1::FAULT_TYPE_SENSOR_DROPOUT);
  sensor.set_robot_id("omni1");
  sensor.set_sensor_name("sonar");
  EXPECT_EQ(Inject(sensor).error_code(), grpc::StatusCode::NOT_FOUND);
  sensor.set_sensor_name("laser");
  sensor.set_duration_s(1.0);
  EXPECT_TRUE(Inject(sensor).ok());

  v1::InjectFaultRequest slip;
  slip.set_type(v1::FAULT_TYPE_WHEEL_SLIP_REGION);
  slip.mutable_region_min()->set_x_m(-1);
  slip.mutable_region_min()->set_y_m(-1);
  slip.mutable_region_max()->set_x_m(1);
  slip.mutable_region_max()->set_y_m(1);
  EXPECT_EQ(Inject(slip).error_code(), grpc::StatusCode::INVALID_ARGUMENT);  // no factor
  slip.set_factor(0.7);
  EXPECT_TRUE(Inject(slip).ok());
}

TEST_F(SimServiceFaultsTest, ResetStartsOver) {
  Step(25);
  EXPECT_EQ(Truth().tick(), 25u);
  grpc::ClientContext context;
  v1::ResetRequest request;
  request.set_seed(77);
  v1::ResetResponse response;
  ASSERT_TRUE(stub_->Reset(&context, request, &response).ok());
  const v1::GroundTruth truth = Truth();
  EXPECT_EQ(truth.tick(), 0u);
  ASSERT_EQ(truth.robots_size(), 1);
  EXPECT_EQ(truth.robots(0).robot_id(), "omni1");
  EXPECT_NEAR(truth.robots(0).pose().x_m(), -8.0, 1e-12);
}

}  // namespace
}  // namespace fleetnav
