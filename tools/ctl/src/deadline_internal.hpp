#pragma once

#include <grpcpp/client_context.h>

#include <chrono>

#include "fleetnav/ctl/commands.hpp"

namespace fleetnav::ctl {

/// Gives a unary call the command's deadline (--timeout-s).
inline void SetDeadline(const CommandContext& context, grpc::ClientContext* rpc) {
  rpc->set_deadline(std::chrono::system_clock::now() +
                    std::chrono::milliseconds(static_cast<int64_t>(context.timeout_s * 1000)));
}

}  // namespace fleetnav::ctl
