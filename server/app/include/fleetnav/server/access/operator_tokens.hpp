#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/operator_role.hpp"
#include "fleetnav/server/access/access_policy.hpp"
#include "fleetnav/storage/operator_token_repository.hpp"

namespace fleetnav::server {

/// Where an operator token comes from: the server's token file (`--tokens`, changed by editing
/// it and restarting) or AccessService (kept in the database, revocable at run time).
enum class TokenSource { kFile, kStore };

absl::string_view TokenSourceName(TokenSource source);

/// One token as an admin sees it: never its secret nor its hash.
struct TokenListing {
  std::string name;
  Role role = Role::kViewer;
  TokenSource source = TokenSource::kFile;
  int64_t created_unix_ms = 0;  ///< 0 for the file's tokens
};

/// A token just made: the secret is shown this once and is nowhere kept.
struct IssuedToken {
  std::string name;
  Role role = Role::kViewer;
  std::string secret;  ///< 64 hex digits of 32 random bytes
  int64_t created_unix_ms = 0;
};

/// The operator tokens fleetnavd accepts, managed at run time: the token file's tokens, fixed,
/// and the tokens admins create and revoke, stored as SHA-256 hashes. Every change builds the
/// whole AccessPolicy anew and hands it to `install` (the transport's gate), so a revoked
/// token is refused from the next call on; a change that cannot be stored is not installed,
/// and one that would make the policy invalid is not stored. Thread-safe.
class OperatorTokenService {
 public:
  using PolicyInstaller = std::function<void(std::shared_ptr<const AccessPolicy>)>;

  OperatorTokenService(storage::OperatorTokenRepository* store,
                       std::vector<OperatorToken> file_tokens, const Clock* clock,
                       PolicyInstaller install);

  /// Reads the stored tokens and installs the policy. A stored token whose name or secret the
  /// file also has is left out (the file wins); each such conflict is returned as a message
  /// for the log.
  absl::StatusOr<std::vector<std::string>> Load();

  /// InvalidArgument for a name that is not 1-64 of [A-Za-z0-9._-]; AlreadyExists for a name
  /// in use (in the file or the store).
  absl::StatusOr<IssuedToken> Create(absl::string_view name, Role role);
  /// The file's tokens, then the stored ones, each ordered by name.
  std::vector<TokenListing> List() const;
  /// NotFound for an unknown name; FailedPrecondition for a token of the file.
  absl::Status Revoke(absl::string_view name);

 private:
  /// The policy of the file's tokens and `stored`.
  absl::StatusOr<std::shared_ptr<const AccessPolicy>> BuildPolicy(
      const std::vector<storage::StoredOperatorToken>& stored) const;
  bool InFile(absl::string_view name) const;

  storage::OperatorTokenRepository* store_;
  const std::vector<OperatorToken> file_tokens_;
  const Clock* clock_;
  PolicyInstaller install_;
  mutable absl::Mutex mutex_;
  std::vector<storage::StoredOperatorToken> stored_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav::server
