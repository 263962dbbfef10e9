#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/operator_role.hpp"

namespace fleetnav::storage {

/// An operator token created through the server (AccessService), as stored: its name, role
/// and the SHA-256 of the secret (never the secret), and when it was made.
struct StoredOperatorToken {
  OperatorToken token;
  int64_t created_unix_ms = 0;
};

/// The operator tokens made at run time, so that they outlive a restart and a revocation is
/// final. (Tokens from the server's token file are not stored here.) Thread-safe.
class OperatorTokenRepository {
 public:
  virtual ~OperatorTokenRepository() = default;
  /// AlreadyExists when a token of that name is stored.
  virtual absl::Status InsertToken(const StoredOperatorToken& token) = 0;
  /// Every token, ordered by name.
  virtual absl::StatusOr<std::vector<StoredOperatorToken>> ListTokens() = 0;
  /// NotFound when no token of that name is stored.
  virtual absl::Status DeleteToken(const std::string& name) = 0;
};

}  // namespace fleetnav::storage
