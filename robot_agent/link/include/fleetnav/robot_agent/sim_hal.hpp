#pragma once

#include <grpcpp/channel.h>
#include <grpcpp/client_context.h>

#include <memory>
#include <string>

#include "fleetnav/robot_agent/hal.hpp"
#include "fleetnav/v1/sim_service.grpc.pb.h"

namespace fleetnav::agent {

/// RobotHal over SimService.Attach: one lockstep stream for one simulated robot. NextFrame()
/// reads the tick's frame, Send() answers it. The stream ends (nullopt) when the simulator
/// stops. Not thread-safe: one control loop uses it.
class SimHal final : public RobotHal {
 public:
  /// Opens the stream and attaches to `robot_id`; Attach errors surface on the first read.
  SimHal(std::shared_ptr<grpc::Channel> channel, std::string robot_id);
  ~SimHal() override;

  absl::StatusOr<std::optional<SensorFrame>> NextFrame() override;
  absl::Status Send(const ActuatorCommand& command) override;

 private:
  std::unique_ptr<v1::SimService::Stub> stub_;
  grpc::ClientContext context_;
  std::unique_ptr<grpc::ClientReaderWriter<v1::AttachMessage, v1::SensorFrame>> stream_;
  bool finished_ = false;
};

}  // namespace fleetnav::agent
