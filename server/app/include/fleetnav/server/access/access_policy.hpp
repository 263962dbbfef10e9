#pragma once

#include <string>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "fleetnav/core/operator_role.hpp"

namespace fleetnav::server {

/// SHA-256 of `text` as 64 lower-case hex digits (what `sha256sum` prints).
std::string Sha256Hex(absl::string_view text);

/// What the transport proved about a call's sender.
struct CallerCredentials {
  /// The `authorization` metadata value as sent ("Bearer TOKEN"); empty when absent.
  std::string authorization;
  /// The common name of a client certificate that the server's robot CA verified; empty
  /// when the caller presented none.
  std::string certificate_identity;
};

/// Who a call was admitted as: an operator (name and role) or a robot (its certificate's id).
struct Caller {
  std::string name;
  bool is_robot = false;
  Role role = Role::kViewer;  ///< for operators
};

/// fleetnavd's authorization rules, one per RPC, deny by default. Operators present bearer
/// tokens bound to roles: viewer reads (Get*, List*, Watch*, PlanPaths), operator also runs jobs
/// (SubmitJob, CancelJob, PauseJob, ResumeJob), admin also changes the site and the fleet
/// (Put*/Delete* of maps, marker sets and routes, ForgetRobot, and AccessService's tokens). The
/// HTTP port's reads (the dashboard, /metrics) count as the method "/fleetnav.http/Read" (viewer)
/// and the dashboard's pause, resume and cancel buttons as "/fleetnav.http/Act" (operator). Robots
/// present a client certificate: it admits the agent stream (AgentService/Connect; that the
/// certificate's id equals the robot id the stream's hello claims is checked by the stream) and the
/// reads an agent makes of its site (maps, marker sets, routes). The health service is open to all
/// (load balancers and systemd probe it). Any other method is refused. A missing, malformed or
/// unknown credential is UNAUTHENTICATED; a known caller without the role is PERMISSION_DENIED;
/// both name the method and, for a denial, the role needed. Immutable after Create; thread-safe.
class AccessPolicy {
 public:
  /// InvalidArgument for a token of a malformed hash, or a name or hash given twice.
  static absl::StatusOr<AccessPolicy> Create(std::vector<OperatorToken> tokens);

  /// Decides one call to `method` (the gRPC path, "/package.Service/Method").
  absl::StatusOr<Caller> Authorize(absl::string_view method,
                                   const CallerCredentials& credentials) const;

  size_t token_count() const { return by_hash_.size(); }

 private:
  AccessPolicy() = default;
  absl::StatusOr<Caller> AuthorizeOperator(absl::string_view method, Role needed,
                                           const CallerCredentials& credentials) const;

  absl::flat_hash_map<std::string, OperatorToken> by_hash_;  ///< by sha256_hex
};

}  // namespace fleetnav::server
