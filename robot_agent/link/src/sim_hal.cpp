#include "fleetnav/robot_agent/sim_hal.hpp"

#include <chrono>

#include "absl/strings/str_cat.h"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/proto/sensor_convert.hpp"

namespace fleetnav::agent {

SimHal::SimHal(std::shared_ptr<grpc::Channel> channel, std::string robot_id)
    : stub_(v1::SimService::NewStub(channel)) {
  stream_ = stub_->Attach(&context_);
  v1::AttachMessage attach;
  attach.mutable_attach()->set_robot_id(std::move(robot_id));
  stream_->Write(attach);
}

absl::Status SimHal::CheckRobotKind(const std::shared_ptr<grpc::Channel>& channel,
                                    const std::string& robot_id, const std::string& kind_name,
                                    double timeout_s) {
  std::unique_ptr<v1::SimService::Stub> stub = v1::SimService::NewStub(channel);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() +
                       std::chrono::milliseconds(static_cast<int64_t>(timeout_s * 1000.0)));
  context.set_wait_for_ready(true);
  v1::GetWorldResponse world;
  absl::Status status = FromGrpcStatus(stub->GetWorld(&context, v1::GetWorldRequest(), &world));
  if (!status.ok()) {
    return absl::Status(status.code(),
                        absl::StrCat("simulator did not describe its world: ", status.message()));
  }
  for (const v1::SimRobotInfo& robot : world.robots()) {
    if (robot.robot_id() != robot_id) continue;
    if (robot.model().kind_name() != kind_name) {
      return absl::FailedPreconditionError(
          absl::StrCat("--kind ", kind_name, " does not match the simulator's robot '", robot_id,
                       "', which is a ", robot.model().kind_name()));
    }
    return absl::OkStatus();
  }
  return absl::NotFoundError(absl::StrCat("the simulator's world '", world.world_name(),
                                          "' has no robot '", robot_id, "'"));
}

SimHal::~SimHal() {
  if (!finished_) {
    v1::AttachMessage detach;
    detach.mutable_detach();
    stream_->Write(detach);
    stream_->WritesDone();
    // Finish() only returns once every server message has been read: drain the last frames.
    v1::SensorFrame unread;
    while (stream_->Read(&unread)) {
    }
    (void)stream_->Finish();
  }
}

absl::StatusOr<std::optional<SensorFrame>> SimHal::NextFrame() {
  v1::SensorFrame frame;
  if (stream_->Read(&frame)) return std::optional<SensorFrame>(FromProto(frame));
  finished_ = true;
  stream_->WritesDone();
  absl::Status status = FromGrpcStatus(stream_->Finish());
  if (!status.ok()) return status;
  return std::optional<SensorFrame>();
}

absl::Status SimHal::Send(const ActuatorCommand& command) {
  v1::AttachMessage message;
  *message.mutable_command() = ToProto(command);
  if (!stream_->Write(message)) return absl::UnavailableError("simulator stream closed");
  return absl::OkStatus();
}

}  // namespace fleetnav::agent
