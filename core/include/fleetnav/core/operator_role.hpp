#pragma once

#include <string>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace fleetnav {

/// What an operator's bearer token lets them do; each role includes the ones before it: a
/// viewer reads, an operator also runs jobs, an admin also changes the site, the fleet and the
/// tokens (docs/security.md).
enum class Role { kViewer = 0, kOperator = 1, kAdmin = 2 };

absl::string_view RoleName(Role role);
/// "viewer", "operator" or "admin"; InvalidArgument naming the text otherwise.
absl::StatusOr<Role> ParseRole(absl::string_view text);

/// One operator's bearer token as the server keeps it: only the SHA-256 of the token (hex), so
/// neither the token file nor the database holds a secret.
struct OperatorToken {
  std::string name;
  Role role = Role::kViewer;
  std::string sha256_hex;  ///< 64 lower-case hex digits
};

}  // namespace fleetnav
