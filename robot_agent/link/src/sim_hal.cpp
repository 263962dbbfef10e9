#include "fleetnav/robot_agent/sim_hal.hpp"

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
