// grpc.health.v1.Health as fleetnavd serves it, over real loopback gRPC: Check and Watch for the
// whole server and each service, unknown names refused, and watchers released on shutdown.
#include <gtest/gtest.h>

#include <thread>

#include "fleet_fixture.hpp"
#include "grpc/health/v1/health.grpc.pb.h"

namespace fleetnav {
namespace {

using grpc::health::v1::HealthCheckRequest;
using grpc::health::v1::HealthCheckResponse;

class HealthTest : public testing::FleetServerFixture {
 protected:
  void SetUp() override {
    FleetServerFixture::SetUp();
    health_ = grpc::health::v1::Health::NewStub(channel_);
  }

  grpc::Status Check(const std::string& service, HealthCheckResponse* response) {
    grpc::ClientContext context;
    HealthCheckRequest request;
    request.set_service(service);
    return health_->Check(&context, request, response);
  }

  std::unique_ptr<grpc::health::v1::Health::Stub> health_;
};

TEST_F(HealthTest, TheServerAndItsServicesAreServingAndUnknownNamesAreNotFound) {
  for (const std::string service : {"", "fleetnav.v1.FleetService", "fleetnav.v1.AgentService"}) {
    SCOPED_TRACE(service);
    HealthCheckResponse response;
    ASSERT_TRUE(Check(service, &response).ok());
    EXPECT_EQ(response.status(), HealthCheckResponse::SERVING);
  }
  HealthCheckResponse response;
  EXPECT_EQ(Check("fleetnav.v1.NoSuchService", &response).error_code(),
            grpc::StatusCode::NOT_FOUND);
}

TEST_F(HealthTest, WatchSendsTheStatusAndEndsWhenTheServerStops) {
  grpc::ClientContext unknown_context;
  HealthCheckRequest unknown;
  unknown.set_service("nope");
  auto unknown_reader = health_->Watch(&unknown_context, unknown);
  HealthCheckResponse response;
  ASSERT_TRUE(unknown_reader->Read(&response));
  EXPECT_EQ(response.status(), HealthCheckResponse::SERVICE_UNKNOWN);
  unknown_context.TryCancel();
  (void)unknown_reader->Finish();

  grpc::ClientContext context;
  auto reader = health_->Watch(&context, HealthCheckRequest{});
  ASSERT_TRUE(reader->Read(&response));
  EXPECT_EQ(response.status(), HealthCheckResponse::SERVING);
  std::thread stopper([this] { server_->Shutdown(); });
  while (reader->Read(&response)) {
    EXPECT_EQ(response.status(), HealthCheckResponse::NOT_SERVING);
  }
  (void)reader->Finish();
  stopper.join();
}

}  // namespace
}  // namespace fleetnav
