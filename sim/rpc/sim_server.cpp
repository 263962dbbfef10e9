#include "fleetnav/sim/sim_server.hpp"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/server_builder.h>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::sim {

SimServer::SimServer(WorldDescription world, SimServerParams params)
    : world_(std::move(world)), params_(std::move(params)) {}

SimServer::~SimServer() { Shutdown(); }

absl::StatusOr<int> SimServer::Start() {
  RETURN_IF_ERROR(params_.lockstep.Validate());
  ASSIGN_OR_RETURN(simulation_, Simulation::Create(world_, params_.simulation));
  for (const RobotSpawn& spawn : world_.robots) {
    RETURN_IF_ERROR(simulation_->AddRobot(spawn.robot_id, spawn.kind_name, spawn.pose));
  }
  lockstep_ = std::make_unique<Lockstep>(simulation_.get(), params_.lockstep);
  service_ = std::make_unique<SimServiceImpl>(lockstep_.get(), params_.start_unix_ms);

  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(params_.listen_address, grpc::InsecureServerCredentials(), &port);
  // gRPC binds with SO_REUSEPORT by default: a second server on a bound port would start and
  // the kernel would split the clients between the two. The port must be this server's alone.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.RegisterService(service_.get());
  server_ = builder.BuildAndStart();
  if (server_ == nullptr || port == 0) {
    return absl::UnavailableError(absl::StrCat("cannot listen: address ", params_.listen_address,
                                               " already in use or not available"));
  }
  loop_ = std::thread([this] { lockstep_->Run(); });
  return port;
}

void SimServer::WaitForLoop() {
  if (loop_.joinable()) loop_.join();
}

void SimServer::Shutdown() {
  if (shut_down_ || lockstep_ == nullptr) return;
  shut_down_ = true;
  lockstep_->Stop();
  WaitForLoop();
  if (server_ != nullptr) {
    server_->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(1));
    server_->Wait();
  }
}

}  // namespace fleetnav::sim
