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

namespace fleetnav::sim {
namespace {

v1::Twist2 ToProto(const Twist2& twist) {
  v1::Twist2 out;
  out.set_vx_mps(twist.vx_mps);
  out.set_vy_mps(twist.vy_mps);
  out.set_yaw_rate_radps(twist.yaw_rate_radps);
  return out;
}

}  // namespace

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
  lockstep_->Inspect([&](const Simulation& simulation) {
    const WorldDescription& world = simulation.world();
    response->set_world_name(world.name);
    response->set_width_m(world.max_corner_m.x() - world.min_corner_m.x());
    response->set_height_m(world.max_corner_m.y() - world.min_corner_m.y());
    response->set_control_period_s(simulation.params().control_period_s);
    response->set_physics_step_s(simulation.params().physics_step_s);
    response->set_sim_time_ns(simulation.now_ns());
    for (const std::string& id : simulation.robot_ids()) {
      v1::SimRobotInfo* info = response->add_robots();
      info->set_robot_id(id);
      info->set_attached(std::binary_search(attached.begin(), attached.end(), id));
      absl::StatusOr<RobotModel> model = simulation.ModelOf(id);
      if (model.ok()) *info->mutable_model() = fleetnav::ToProto(*model);
    }
  });
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
  const GroundTruthSnapshot truth = lockstep_->GroundTruth();
  response->set_sim_time_ns(truth.sim_time_ns);
  response->set_tick(truth.tick);
  response->set_start_unix_ms(start_unix_ms_);
  for (const RobotTruth& robot : truth.robots) {
    v1::RobotGroundTruth* wire = response->add_robots();
    wire->set_robot_id(robot.robot_id);
    *wire->mutable_pose() = fleetnav::ToProto(robot.pose);
    *wire->mutable_velocity() = ToProto(robot.velocity);
    wire->set_up_z(robot.up_z);
    wire->set_collisions(static_cast<uint32_t>(robot.collisions()));
    wire->set_collisions_world(static_cast<uint32_t>(robot.collisions_world));
    wire->set_collisions_robots(static_cast<uint32_t>(robot.collisions_robots));
  }
  for (const TrolleyTruth& trolley : truth.trolleys) {
    v1::TrolleyGroundTruth* wire = response->add_trolleys();
    wire->set_trolley_id(trolley.trolley_id);
    *wire->mutable_pose() = fleetnav::ToProto(trolley.pose);
    wire->set_carrier_robot_id(trolley.carrier_robot_id);
  }
  for (const SimContact& contact : truth.contacts) {
    v1::Contact* wire = response->add_contacts();
    wire->set_robot_id(contact.robot_id);
    wire->set_other(contact.other);
    wire->set_sim_time_ns(contact.sim_time_ns);
  }
  response->set_min_separation_m(std::isfinite(truth.min_separation_m) ? truth.min_separation_m
                                                                       : 1e9);
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
  FaultSpec fault;
  switch (request->type()) {
    case v1::FAULT_TYPE_HIDE_ULTRASONIC_REGION:
      fault.type = FaultType::kHideUltrasonicRegion;
      break;
    case v1::FAULT_TYPE_REMOVE_FENCE_SEGMENT:
      fault.type = FaultType::kRemoveFenceSegment;
      break;
    case v1::FAULT_TYPE_REMOVE_STRIPE_SEGMENT:
      fault.type = FaultType::kRemoveStripeSegment;
      break;
    case v1::FAULT_TYPE_WHEEL_SLIP_REGION:
      fault.type = FaultType::kWheelSlipRegion;
      break;
    case v1::FAULT_TYPE_SENSOR_DROPOUT:
      fault.type = FaultType::kSensorDropout;
      break;
    case v1::FAULT_TYPE_SLOW_DOWN:
      fault.type = FaultType::kSlowDown;
      break;
    default:
      return ToGrpcStatus(absl::InvalidArgumentError(absl::StrCat(
          "type: unknown or unspecified fault type ", static_cast<int>(request->type()))));
  }
  fault.region_min_m = Eigen::Vector2d(request->region_min().x_m(), request->region_min().y_m());
  fault.region_max_m = Eigen::Vector2d(request->region_max().x_m(), request->region_max().y_m());
  fault.robot_id = request->robot_id();
  fault.sensor_name = request->sensor_name();
  fault.duration_s = request->duration_s();
  // proto3 has no presence for doubles: an unset factor (0) means "no factor given".
  fault.factor = request->factor();
  if (fault.factor == 0.0 && fault.type != FaultType::kSlowDown) fault.factor = 1.0;
  if (fault.type == FaultType::kWheelSlipRegion && request->factor() == 0.0) {
    return ToGrpcStatus(absl::InvalidArgumentError(
        "factor: wheel slip needs the share of traction kept, in (0, 1]"));
  }
  return ToGrpcStatus(lockstep_->InjectFault(fault));
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
