#include "fleetnav/sim/sim_service.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "absl/strings/str_cat.h"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/proto/robot_convert.hpp"
#include "fleetnav/proto/sensor_convert.hpp"
#include "fleetnav/proto/sim_convert.hpp"

namespace fleetnav::sim {
grpc::Status SimServiceImpl::Attach(
    grpc::ServerContext* context,
    grpc::ServerReaderWriter<v1::SensorFrame, v1::AttachMessage>* stream) {
  stream->SendInitialMetadata();
  v1::AttachMessage message;
  if (!stream->Read(&message)) return grpc::Status::OK;
  if (message.payload_case() != v1::AttachMessage::kAttach) {
    return ToGrpcStatus(
        absl::InvalidArgumentError("the first message on an Attach stream must be `attach`"));
  }
  absl::StatusOr<std::unique_ptr<sim::Attachment>> attachment =
      lockstep_->Attach(message.attach().robot_id());
  if (!attachment.ok()) return ToGrpcStatus(attachment.status());

  while (!context->IsCancelled()) {
    std::optional<SensorFrame> frame = (*attachment)->WaitFrame();
    if (!frame) return grpc::Status::OK;  // the simulation stopped
    if (!stream->Write(fleetnav::ToProto(*frame))) break;
    if (!stream->Read(&message)) break;
    if (message.payload_case() == v1::AttachMessage::kDetach) break;
    if (message.payload_case() != v1::AttachMessage::kCommand) {
      return ToGrpcStatus(
          absl::InvalidArgumentError("expected a `command` answering the last frame"));
    }
    absl::StatusOr<ActuatorCommand> command = FromProto(message.command());
    absl::Status submitted = command.ok() ? (*attachment)->Submit(*command) : command.status();
    if (!submitted.ok()) return ToGrpcStatus(submitted);
  }
  return grpc::Status::OK;
}

grpc::Status SimServiceImpl::GetWorld(grpc::ServerContext*, const v1::GetWorldRequest*,
                                      v1::GetWorldResponse* response) {
  const std::vector<std::string> attached = lockstep_->attached_robot_ids();
  SimWorldSummary summary;
  lockstep_->Inspect([&](const Simulation& simulation) {
    const WorldDescription& world = simulation.world();
    summary.world_name = world.name;
    summary.width_m = world.max_corner_m.x() - world.min_corner_m.x();
    summary.height_m = world.max_corner_m.y() - world.min_corner_m.y();
    summary.control_period_s = simulation.params().control_period_s;
    summary.physics_step_s = simulation.params().physics_step_s;
    summary.sim_time_ns = simulation.now_ns();
    for (const std::string& id : simulation.robot_ids()) {
      absl::StatusOr<RobotModel> model = simulation.ModelOf(id);
      summary.robots.push_back({id, model.ok() ? std::optional<RobotModel>(*model) : std::nullopt,
                                std::binary_search(attached.begin(), attached.end(), id)});
    }
  });
  *response = fleetnav::ToProto(summary);
  return grpc::Status::OK;
}

grpc::Status SimServiceImpl::Spawn(grpc::ServerContext*, const v1::SpawnRequest* request,
                                   v1::SpawnResponse*) {
  absl::StatusOr<Pose2> pose = FromProto(request->pose(), "pose");
  if (!pose.ok()) return ToGrpcStatus(pose.status());
  return ToGrpcStatus(lockstep_->Spawn(request->robot_id(), request->kind_name(), *pose));
}

grpc::Status SimServiceImpl::GetGroundTruth(grpc::ServerContext*, const v1::GetGroundTruthRequest*,
                                            v1::GroundTruth* response) {
  *response = fleetnav::ToProto(lockstep_->GroundTruth(), start_unix_ms_);
  return grpc::Status::OK;
}

grpc::Status SimServiceImpl::Reset(grpc::ServerContext*, const v1::ResetRequest* request,
                                   v1::ResetResponse*) {
  lockstep_->Reset(request->seed());
  return grpc::Status::OK;
}

grpc::Status SimServiceImpl::InjectFault(grpc::ServerContext*,
                                         const v1::InjectFaultRequest* request,
                                         v1::InjectFaultResponse*) {
  absl::StatusOr<FaultSpec> fault = FromProto(*request);
  if (!fault.ok()) return ToGrpcStatus(fault.status());
  return ToGrpcStatus(lockstep_->InjectFault(*fault));
}

grpc::Status SimServiceImpl::Step(grpc::ServerContext* context, const v1::StepRequest* request,
                                  v1::StepResponse* response) {
  const uint64_t target = lockstep_->tick() + request->ticks();
  lockstep_->RequestTicks(request->ticks());
  while (lockstep_->tick() < target && !lockstep_->stopped() && !context->IsCancelled()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  response->set_tick(lockstep_->tick());
  response->set_sim_time_ns(lockstep_->now_ns());
  return grpc::Status::OK;
}

grpc::Status SimServiceImpl::RunUntil(grpc::ServerContext*, const v1::RunUntilRequest* request,
                                      v1::RunResponse* response) {
  if (request->sim_time_ns() < 0) {
    return ToGrpcStatus(absl::InvalidArgumentError("sim_time_ns: must be >= 0"));
  }
  lockstep_->RunUntil(lockstep_->FirstTickAtOrAfter(request->sim_time_ns()));
  response->set_tick(lockstep_->tick());
  response->set_sim_time_ns(lockstep_->now_ns());
  return grpc::Status::OK;
}

grpc::Status SimServiceImpl::Run(grpc::ServerContext*, const v1::RunRequest* request,
                                 v1::RunResponse* response) {
  if (!(request->real_time_factor() >= 0.0) || !std::isfinite(request->real_time_factor())) {
    return ToGrpcStatus(absl::InvalidArgumentError("real_time_factor: must be finite and >= 0"));
  }
  lockstep_->SetRealTimeFactor(request->real_time_factor());
  response->set_tick(lockstep_->tick());
  response->set_sim_time_ns(lockstep_->now_ns());
  return grpc::Status::OK;
}

}  // namespace fleetnav::sim
