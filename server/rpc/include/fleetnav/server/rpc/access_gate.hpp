#pragma once

#include <grpcpp/security/auth_context.h>
#include <grpcpp/security/auth_metadata_processor.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/server/access_policy.hpp"

namespace fleetnav::server {

/// How many calls the gate let through and refused, by reason.
struct AccessCounts {
  uint64_t admitted = 0;
  uint64_t unauthenticated = 0;
  uint64_t denied = 0;
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
/// server runs (OperatorTokenService). Thread-safe.
class AccessGate final : public grpc::AuthMetadataProcessor {
 public:
  AccessGate(std::shared_ptr<const AccessPolicy> policy,
             std::function<void(const std::string&)> on_refusal)
      : policy_(std::move(policy)), on_refusal_(std::move(on_refusal)) {}

  /// Applies `policy` from the next call on (tokens created or revoked at run time); calls
  /// already admitted keep running.
  void ReplacePolicy(std::shared_ptr<const AccessPolicy> policy);

  /// Runs on gRPC's own thread: the decision is a hash lookup, nothing blocks.
  bool IsBlocking() const override { return false; }
  grpc::Status Process(const InputMetadata& auth_metadata, grpc::AuthContext* context,
                       OutputMetadata* consumed_auth_metadata,
                       OutputMetadata* response_metadata) override;

  /// PermissionDenied unless `robot_id` is the certificate's identity (a robot cannot
  /// impersonate another).
  absl::Status CheckRobotClaim(const grpc::AuthContext& context, absl::string_view robot_id);

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
  std::atomic<uint64_t> admitted_{0};
  std::atomic<uint64_t> unauthenticated_{0};
  std::atomic<uint64_t> denied_{0};
};

}  // namespace fleetnav::server
