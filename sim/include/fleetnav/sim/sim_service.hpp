#pragma once

#include "fleetnav/sim/lockstep.hpp"
#include "fleetnav/v1/sim_service.grpc.pb.h"

namespace fleetnav::sim {

/// gRPC edge of SimService over a Lockstep: Attach streams one robot's frames and commands,
/// the rest describe, spawn, reset, inject faults, query ground truth and pace the run.
/// Thread-safe.
class SimServiceImpl final : public v1::SimService::Service {
 public:
  /// start_unix_ms: the calendar at sim time 0 (GroundTruth.start_unix_ms; 0 for none).
  explicit SimServiceImpl(Lockstep* lockstep, int64_t start_unix_ms = 0)
      : lockstep_(lockstep), start_unix_ms_(start_unix_ms) {}

  grpc::Status Attach(
      grpc::ServerContext* context,
      grpc::ServerReaderWriter<v1::SensorFrame, v1::AttachMessage>* stream) override;
  grpc::Status GetWorld(grpc::ServerContext* context, const v1::GetWorldRequest* request,
                        v1::GetWorldResponse* response) override;
  grpc::Status Spawn(grpc::ServerContext* context, const v1::SpawnRequest* request,
                     v1::SpawnResponse* response) override;
  grpc::Status GetGroundTruth(grpc::ServerContext* context,
                              const v1::GetGroundTruthRequest* request,
                              v1::GroundTruth* response) override;
  grpc::Status Reset(grpc::ServerContext* context, const v1::ResetRequest* request,
                     v1::ResetResponse* response) override;
  grpc::Status InjectFault(grpc::ServerContext* context, const v1::InjectFaultRequest* request,
                           v1::InjectFaultResponse* response) override;
  grpc::Status Step(grpc::ServerContext* context, const v1::StepRequest* request,
                    v1::StepResponse* response) override;
  grpc::Status Run(grpc::ServerContext* context, const v1::RunRequest* request,
                   v1::RunResponse* response) override;
  grpc::Status RunUntil(grpc::ServerContext* context, const v1::RunUntilRequest* request,
                        v1::RunResponse* response) override;

 private:
  Lockstep* lockstep_;
  int64_t start_unix_ms_;
};

}  // namespace fleetnav::sim
