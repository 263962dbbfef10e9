#pragma once

#include <grpcpp/security/auth_context.h>
#include <grpcpp/security/auth_metadata_processor.h>
#include <grpcpp/server_context.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/server/access/access_control.hpp"

namespace fleetnav::server {

/// The common name of the client certificate the TLS handshake verified against the robot
/// CA; empty when the caller presented none (or the channel is not TLS).
std::string CertificateIdentity(const grpc::AuthContext& context);

/// fleetnavd's authorization on the wire: gRPC calls it for every call on a TLS port (before
/// any handler runs, for every service, unary and streaming alike) with the call's metadata,
/// among it the method's `:path` and the `authorization` header, and the connection's
/// verified peer, and asks the app's AccessControl (which applies the policy in force, counts
/// and reports). It also checks, for the agent stream, that the robot id a hello claims is the
/// certificate's. With a relay key (the leader of fleetnavd replicas) it
/// also takes calls a replica relayed: such a call carries the key (kRelayKeyHeader, consumed
/// here) and, for a robot, the robot id whose certificate the replica verified
/// (kRelayedRobotHeader), which then stands for the connection's certificate; a call with
/// either header and no matching key is refused UNAUTHENTICATED, so a header that reaches a
/// handler was vouched for. Thread-safe.
class AccessGate final : public grpc::AuthMetadataProcessor {
 public:
  /// `relay_key`: ReplicaRelayKey of the server's key, or empty to take no relayed calls.
  AccessGate(std::shared_ptr<AccessControl> control, std::string relay_key = "")
      : control_(std::move(control)), relay_key_(std::move(relay_key)) {}

  bool IsBlocking() const override { return false; }
  grpc::Status Process(const InputMetadata& auth_metadata, grpc::AuthContext* context,
                       OutputMetadata* consumed_auth_metadata,
                       OutputMetadata* response_metadata) override;

  /// PermissionDenied unless `robot_id` is the identity the call's certificate proved: the
  /// connection's, or the one a replica relayed (a robot cannot impersonate another). For calls
  /// on the TLS port, which the gate saw.
  absl::Status CheckRobotClaim(const grpc::ServerContextBase& call, absl::string_view robot_id);

 private:
  std::shared_ptr<AccessControl> control_;
  const std::string relay_key_;
};

}  // namespace fleetnav::server
