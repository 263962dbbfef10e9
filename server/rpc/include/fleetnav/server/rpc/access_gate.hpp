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
#include "fleetnav/server/access/access_policy.hpp"

namespace fleetnav::server {

/// How many calls the gate let through and refused, by reason.
struct AccessCounts {
  uint64_t admitted = 0;
  uint64_t unauthenticated = 0;
  uint64_t denied = 0;
  /// TLS handshakes refused before any call (TlsFrontDoor): plaintext clients, certificates
  /// of another CA, expired ones.
  uint64_t handshakes_refused = 0;
};

/// The common name of the client certificate the TLS handshake verified against the robot
/// CA; empty when the caller presented none (or the channel is not TLS).
std::string CertificateIdentity(const grpc::AuthContext& context);

/// fleetnavd's authorization on the wire: gRPC calls it for every call on a TLS port (before
/// any handler runs, for every service, unary and streaming alike) with the call's metadata,
/// among it the method's `:path` and the `authorization` header, and the connection's
/// verified peer. It applies the AccessPolicy, counts the outcome, and reports each refusal
/// (method, caller, reason) to `on_refusal` for the log. It also checks, for the agent stream,
/// that the robot id a hello claims is the certificate's. The policy can be replaced while the
/// server runs (OperatorTokenService). With a relay key (the leader of fleetnavd replicas) it
/// also takes calls a replica relayed: such a call carries the key (kRelayKeyHeader, consumed
/// here) and, for a robot, the robot id whose certificate the replica verified
/// (kRelayedRobotHeader), which then stands for the connection's certificate; a call with
/// either header and no matching key is refused UNAUTHENTICATED, so a header that reaches a
/// handler was vouched for. Thread-safe.
class AccessGate final : public grpc::AuthMetadataProcessor {
 public:
  /// `relay_key`: ReplicaRelayKey of the server's key, or empty to take no relayed calls.
  AccessGate(std::shared_ptr<const AccessPolicy> policy,
             std::function<void(const std::string&)> on_refusal, std::string relay_key = "")
      : policy_(std::move(policy)),
        on_refusal_(std::move(on_refusal)),
        relay_key_(std::move(relay_key)) {}

  /// Applies `policy` from the next call on (tokens created or revoked at run time); calls
  /// already admitted keep running.
  void ReplacePolicy(std::shared_ptr<const AccessPolicy> policy);

  /// Runs on gRPC's own thread: the decision is a hash lookup, nothing blocks.
  bool IsBlocking() const override { return false; }
  grpc::Status Process(const InputMetadata& auth_metadata, grpc::AuthContext* context,
                       OutputMetadata* consumed_auth_metadata,
                       OutputMetadata* response_metadata) override;

  /// PermissionDenied unless `robot_id` is the identity the call's certificate proved: the
  /// connection's, or the one a replica relayed (a robot cannot impersonate another). For calls
  /// on the TLS port, which the gate saw.
  absl::Status CheckRobotClaim(const grpc::ServerContextBase& call, absl::string_view robot_id);

  /// The HTTP port's check of an `Authorization` header: `action` for the dashboard's buttons
  /// (operator), else a read (viewer). Counted and reported like the RPCs.
  absl::StatusOr<Caller> AuthorizeHttp(bool action, absl::string_view authorization);

  AccessCounts counts() const;

 private:
  void Refused(const absl::Status& status);
  std::shared_ptr<const AccessPolicy> policy() const;

  mutable absl::Mutex policy_mutex_;
  std::shared_ptr<const AccessPolicy> policy_ ABSL_GUARDED_BY(policy_mutex_);
  std::function<void(const std::string&)> on_refusal_;
  const std::string relay_key_;
  std::atomic<uint64_t> admitted_{0};
  std::atomic<uint64_t> unauthenticated_{0};
  std::atomic<uint64_t> denied_{0};
};

}  // namespace fleetnav::server
