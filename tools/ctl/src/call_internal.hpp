#pragma once

#include <grpcpp/client_context.h>

#include <chrono>
#include <string>

#include "fleetnav/ctl/commands.hpp"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"

namespace fleetnav::ctl {

/// Sends the operator's token with a call (`authorization: Bearer TOKEN`).
inline void AddToken(const CommandContext& context, grpc::ClientContext* rpc) {
  if (!context.token.empty()) rpc->AddMetadata("authorization", "Bearer " + context.token);
}

/// Prepares a unary call: the command's deadline (--timeout-s) and the operator's token
/// (`authorization: Bearer TOKEN`, --token or FLEETNAV_TOKEN).
inline void PrepareCall(const CommandContext& context, grpc::ClientContext* rpc) {
  rpc->set_deadline(std::chrono::system_clock::now() +
                    std::chrono::milliseconds(static_cast<int64_t>(context.timeout_s * 1000)));
  AddToken(context, rpc);
}

/// One FleetService call with the command's deadline; prints what `done()` says on success.
template <typename Done, typename Call>
absl::Status CallAndSay(const CommandContext& context, Done done, Call call) {
  auto stub = v1::FleetService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  if (absl::Status s = FromGrpcStatus(call(*stub, &rpc)); !s.ok()) return s;
  *context.out << done() << '\n';
  return absl::OkStatus();
}

}  // namespace fleetnav::ctl
