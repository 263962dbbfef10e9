#pragma once

#include <grpcpp/client_context.h>

#include <chrono>
#include <string>

#include "fleetnav/ctl/commands.hpp"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"

namespace fleetnav::ctl {

/// Gives a unary call the command's deadline (--timeout-s).
inline void SetDeadline(const CommandContext& context, grpc::ClientContext* rpc) {
  rpc->set_deadline(std::chrono::system_clock::now() +
                    std::chrono::milliseconds(static_cast<int64_t>(context.timeout_s * 1000)));
}

/// One FleetService call with the command's deadline; prints `done` on success.
template <typename Call>
absl::Status CallAndSay(const CommandContext& context, const std::string& done, Call call) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  SetDeadline(context, &rpc);
  if (absl::Status s = FromGrpcStatus(call(*stub, &rpc)); !s.ok()) return s;
  *context.out << done << '\n';
  return absl::OkStatus();
}

}  // namespace fleetnav::ctl
