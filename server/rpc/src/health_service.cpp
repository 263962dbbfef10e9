#include "fleetnav/server/rpc/health_service.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

#include "fleetnav/proto/grpc_status.hpp"

namespace fleetnav::server {

using grpc::health::v1::HealthCheckResponse;

HealthCheckResponse::ServingStatus HealthServiceImpl::StatusOf(const std::string& service) const {
  if (!service.empty() &&
      std::find(services_.begin(), services_.end(), service) == services_.end()) {
    return HealthCheckResponse::SERVICE_UNKNOWN;
  }
  return stopping_->load() ? HealthCheckResponse::NOT_SERVING : HealthCheckResponse::SERVING;
}

grpc::Status HealthServiceImpl::Check(grpc::ServerContext*,
                                      const grpc::health::v1::HealthCheckRequest* request,
                                      HealthCheckResponse* response) {
  const HealthCheckResponse::ServingStatus status = StatusOf(request->service());
  if (status == HealthCheckResponse::SERVICE_UNKNOWN) {
    return ToGrpcStatus(absl::NotFoundError("service '" + request->service() + "' unknown"));
  }
  response->set_status(status);
  return grpc::Status::OK;
}

grpc::Status HealthServiceImpl::Watch(grpc::ServerContext* context,
                                      const grpc::health::v1::HealthCheckRequest* request,
                                      grpc::ServerWriter<HealthCheckResponse>* writer) {
  HealthCheckResponse response;
  bool first = true;
  while (!context->IsCancelled()) {
    const HealthCheckResponse::ServingStatus status = StatusOf(request->service());
    if (first || status != response.status()) {
      first = false;
      response.set_status(status);
      if (!writer->Write(response)) break;
    }
    if (stopping_->load()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return grpc::Status::OK;
}

}  // namespace fleetnav::server
