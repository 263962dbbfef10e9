#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "grpc/health/v1/health.grpc.pb.h"

namespace fleetnav::server {

/// grpc.health.v1.Health on the synchronous API, in place of gRPC's default health service.
/// The default one is a callback-API service, and the callback API runs two extra threads that
/// poll every socket of the process; at 5,000 robots their hand-offs to the agent-stream threads
/// cost about a sixth of fleetnavd's CPU. Check: SERVING for "" and each of `services` while the
/// server runs, NOT_SERVING once `stopping` is set, NOT_FOUND for any other name. Watch: the
/// status now and on every change (SERVICE_UNKNOWN for other names), until the caller cancels or
/// the server stops. Thread-safe.
class HealthServiceImpl final : public grpc::health::v1::Health::Service {
 public:
  HealthServiceImpl(std::vector<std::string> services, const std::atomic<bool>* stopping)
      : services_(std::move(services)), stopping_(stopping) {}

  grpc::Status Check(grpc::ServerContext* context,
                     const grpc::health::v1::HealthCheckRequest* request,
                     grpc::health::v1::HealthCheckResponse* response) override;
  grpc::Status Watch(grpc::ServerContext* context,
                     const grpc::health::v1::HealthCheckRequest* request,
                     grpc::ServerWriter<grpc::health::v1::HealthCheckResponse>* writer) override;

 private:
  grpc::health::v1::HealthCheckResponse::ServingStatus StatusOf(const std::string& service) const;

  const std::vector<std::string> services_;
  const std::atomic<bool>* stopping_;
};

}  // namespace fleetnav::server
