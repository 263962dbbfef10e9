#pragma once

#include <grpcpp/channel.h>
#include <grpcpp/client_context.h>

#include <memory>
#include <optional>
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

  /// Asks the simulator (GetWorld) for `robot_id` before attaching: NotFound when it has no
  /// such robot, FailedPrecondition naming both kinds when its kind is not `kind_name`.
  static absl::Status CheckRobotKind(const std::shared_ptr<grpc::Channel>& channel,
                                     const std::string& robot_id, const std::string& kind_name,
                                     double timeout_s = 10.0);

  absl::StatusOr<std::optional<SensorFrame>> NextFrame() override;
  absl::Status Send(const ActuatorCommand& command) override;

 private:
  std::unique_ptr<v1::SimService::Stub> stub_;
  grpc::ClientContext context_;
  std::unique_ptr<grpc::ClientReaderWriter<v1::AttachMessage, v1::SensorFrame>> stream_;
  bool finished_ = false;
};

}  // namespace fleetnav::agent
