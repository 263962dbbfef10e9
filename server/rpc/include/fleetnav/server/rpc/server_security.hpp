#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/server/access/access_policy.hpp"

namespace fleetnav::server {

/// Where fleetnavd's TLS and credential files are (fleetnavd --tls-cert, --tls-key,
/// --tls-client-ca, --tokens, or the config's `tls:` section).
struct ServerSecurityFiles {
  std::string cert_path;       ///< the server's certificate chain (PEM)
  std::string key_path;        ///< its private key (PEM)
  std::string client_ca_path;  ///< the CA that signs robot certificates (PEM)
  std::string tokens_path;     ///< operator tokens (YAML, see ParseOperatorTokens)

  bool empty() const {
    return cert_path.empty() && key_path.empty() && client_ca_path.empty() && tokens_path.empty();
  }
};

/// The files' contents, checked: the certificate and key parse and belong together, the CA
/// parses, the tokens build an AccessPolicy.
struct ServerSecurity {
  std::string cert_chain_pem;
  std::string private_key_pem;
  std::string client_ca_pem;
  std::vector<OperatorToken> tokens;
};

/// Reads and checks every file; NotFound naming an unreadable file, InvalidArgument naming a
/// file that is not what it should be (not PEM, a key that does not match the certificate, an
/// expired server certificate, a bad token entry).
absl::StatusOr<ServerSecurity> LoadServerSecurity(const ServerSecurityFiles& files);

/// Operator tokens YAML:
///   tokens:
///     - {name: alice, role: admin, sha256: <64 hex digits>}   # sha256sum of the token
///     - {name: night-shift, role: operator, sha256: ...}
/// InvalidArgument naming the entry for unknown keys, roles or malformed hashes.
absl::StatusOr<std::vector<OperatorToken>> ParseOperatorTokens(absl::string_view yaml_text);

}  // namespace fleetnav::server
