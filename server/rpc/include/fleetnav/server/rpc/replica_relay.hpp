#pragma once

#include <string>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace fleetnav::server {

/// Metadata a fleetnavd replica adds to every call it relays to the site's leader over TLS
/// (docs/security.md, "Replicas"): the relay key proves that a replica sent the call, and the
/// relayed robot id is the common name of the robot certificate the replica verified on the
/// caller's connection (absent when the caller showed none). The leader's AccessGate trusts the
/// robot id only with the right key and refuses a call that carries either header wrongly.
inline constexpr char kRelayKeyHeader[] = "fleetnav-relay-key";
inline constexpr char kRelayedRobotHeader[] = "fleetnav-relayed-robot";

/// The relay key of the replicas that share the server key `private_key_pem`: HMAC-SHA256 of
/// that key (DER) over a fixed label, as 64 hex digits. Only holders of the server's private
/// key can make it; it never changes while the key does not. InvalidArgument when the PEM
/// holds no private key.
absl::StatusOr<std::string> ReplicaRelayKey(const std::string& private_key_pem);

/// Whether `presented` is `relay_key` (compared in constant time; an empty key never matches).
bool IsReplicaRelayKey(absl::string_view presented, absl::string_view relay_key);

/// The first certificate of a PEM chain (the server's own, without its issuers), as PEM: what
/// a replica pins when it connects to the leader. InvalidArgument when there is none.
absl::StatusOr<std::string> LeafCertificatePem(const std::string& chain_pem);

}  // namespace fleetnav::server
