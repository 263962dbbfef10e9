#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/server/access/access_policy.hpp"

namespace fleetnav::server {

/// How many calls were let through and refused, by reason.
struct AccessCounts {
  uint64_t admitted = 0;
  uint64_t unauthenticated = 0;
  uint64_t denied = 0;
  /// TLS handshakes refused before any call (TlsFrontDoor): plaintext clients, certificates
  /// of another CA, expired ones.
  uint64_t handshakes_refused = 0;
};

/// fleetnavd's authorization, whatever the transport: it holds the AccessPolicy in force
/// (replaced while the server runs when tokens are created or revoked), applies it to each
/// caller, counts the outcomes and reports every refusal (method, caller and reason) to
/// `on_refusal` for the log. The gRPC gate (rpc/AccessGate) and the HTTP port both ask it, so a
/// token means the same on either. Thread-safe.
class AccessControl {
 public:
  AccessControl(std::shared_ptr<const AccessPolicy> policy,
                std::function<void(const std::string&)> on_refusal)
      : policy_(std::move(policy)), on_refusal_(std::move(on_refusal)) {}

  /// The policy's decision for `method` (a gRPC path), counted and reported.
  absl::StatusOr<Caller> Authorize(absl::string_view method, const CallerCredentials& credentials);
  /// The HTTP port's check of an `Authorization` header: `action` for the dashboard's buttons
  /// (operator), else a read (viewer). Counted and reported like the RPCs.
  absl::StatusOr<Caller> AuthorizeHttp(bool action, absl::string_view authorization);
  /// Counts and reports a refusal decided outside the policy (a relayed call without the
  /// relay key, a robot claiming another's id).
  void Refused(const absl::Status& status);

  /// Applies `policy` from the next call on.
  void ReplacePolicy(std::shared_ptr<const AccessPolicy> policy);
  AccessCounts counts() const;

 private:
  std::shared_ptr<const AccessPolicy> policy() const;

  mutable absl::Mutex policy_mutex_;
  std::shared_ptr<const AccessPolicy> policy_ ABSL_GUARDED_BY(policy_mutex_);
  std::function<void(const std::string&)> on_refusal_;
  std::atomic<uint64_t> admitted_{0};
  std::atomic<uint64_t> unauthenticated_{0};
  std::atomic<uint64_t> denied_{0};
};

}  // namespace fleetnav::server
