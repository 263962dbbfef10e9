// grpc.health.v1.Health as fleetnavd serves it, over real loopback gRPC: Check and Watch for the
// whole server and each service, unknown names refused, and watchers released on shutdown.
#include <grpcpp/create_channel.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <thread>

#include "fleetnav/server/rpc/fleet_server.hpp"
#include "grpc/health/v1/health.grpc.pb.h"
#include "test_paths.hpp"

namespace fleetnav {
namespace {

using grpc::health::v1::HealthCheckRequest;
using grpc::health::v1::HealthCheckResponse;

class HealthTest : public ::testing::Test {
 protected:
  void SetUp() override {
    db_path_ = testing::UniqueTempPath("health") + ".db";
    server::FleetServerParams params;
    params.listen_address = "127.0.0.1:0";
    params.db_path = db_path_;
    server_ = std::make_unique<server::FleetServer>(params);
    absl::StatusOr<int> port = server_->Start();
    ASSERT_TRUE(port.ok()) << port.status();
    health_ = grpc::health::v1::Health::NewStub(grpc::CreateChannel(
        "127.0.0.1:" + std::to_string(*port), grpc::InsecureChannelCredentials()));
  }
  void TearDown() override {
    server_->Shutdown();
    server_.reset();
    std::filesystem::remove(db_path_);
  }

  grpc::Status Check(const std::string& service, HealthCheckResponse* response) {
    grpc::ClientContext context;
    HealthCheckRequest request;
    request.set_service(service);
    return health_->Check(&context, request, response);
  }

  std::string db_path_;
  std::unique_ptr<server::FleetServer> server_;
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
