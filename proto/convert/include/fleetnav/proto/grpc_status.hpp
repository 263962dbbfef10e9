#pragma once

#include <grpcpp/support/status.h>

#include "absl/status/status.h"

namespace fleetnav {

/// The one mapping from absl::Status to grpc::Status used by every gRPC edge (fleetnavd,
/// fleetnav-sim): the codes share numbers (google.rpc.Code), and the message is kept.
grpc::Status ToGrpcStatus(const absl::Status& status);

/// The reverse, for clients.
absl::Status FromGrpcStatus(const grpc::Status& status);

}  // namespace fleetnav
