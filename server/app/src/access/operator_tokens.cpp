#include "fleetnav/server/access/operator_tokens.hpp"

#include <openssl/rand.h>

#include <algorithm>
#include <array>

#include "absl/strings/escaping.h"
#include "absl/strings/str_cat.h"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::server {
namespace {

constexpr size_t kMaxNameLength = 64;
constexpr size_t kSecretBytes = 32;

absl::Status ValidateName(absl::string_view name) {
  const bool valid_characters = std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
           c == '_' || c == '-';
  });
  if (name.empty() || name.size() > kMaxNameLength || !valid_characters) {
    return absl::InvalidArgumentError(
        absl::StrCat("token name '", EchoInput(std::string_view(name.data(), name.size())),
                     "': must be 1 to ", kMaxNameLength, " of A-Z a-z 0-9 . _ -"));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::string> RandomSecret() {
  std::array<unsigned char, kSecretBytes> bytes{};
  if (RAND_bytes(bytes.data(), static_cast<int>(bytes.size())) != 1) {
    return absl::InternalError("the system's random generator failed; no token was made");
  }
  return absl::BytesToHexString(
      absl::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace

absl::string_view TokenSourceName(TokenSource source) {
  return source == TokenSource::kFile ? "file" : "store";
}

OperatorTokenService::OperatorTokenService(storage::OperatorTokenRepository* store,
                                           std::vector<OperatorToken> file_tokens,
                                           const Clock* clock, PolicyInstaller install)
    : store_(store),
      file_tokens_(std::move(file_tokens)),
      clock_(clock),
      install_(std::move(install)) {}

bool OperatorTokenService::InFile(absl::string_view name) const {
  return std::any_of(file_tokens_.begin(), file_tokens_.end(),
                     [&](const OperatorToken& token) { return token.name == name; });
}

absl::StatusOr<std::shared_ptr<const AccessPolicy>> OperatorTokenService::BuildPolicy(
    const std::vector<storage::StoredOperatorToken>& stored) const {
  std::vector<OperatorToken> tokens = file_tokens_;
  for (const storage::StoredOperatorToken& entry : stored) tokens.push_back(entry.token);
  ASSIGN_OR_RETURN(AccessPolicy policy, AccessPolicy::Create(std::move(tokens)));
  return std::make_shared<const AccessPolicy>(std::move(policy));
}

absl::StatusOr<std::vector<std::string>> OperatorTokenService::Load() {
  ASSIGN_OR_RETURN(std::vector<storage::StoredOperatorToken> stored, store_->ListTokens());
  std::vector<std::string> conflicts;
  std::vector<storage::StoredOperatorToken> kept;
  for (storage::StoredOperatorToken& entry : stored) {
    const bool same_secret = std::any_of(
        file_tokens_.begin(), file_tokens_.end(),
        [&](const OperatorToken& token) { return token.sha256_hex == entry.token.sha256_hex; });
    if (InFile(entry.token.name) || same_secret) {
      conflicts.push_back(absl::StrCat("stored token '", entry.token.name,
                                       "' is left out: the token file has its ",
                                       same_secret ? "secret" : "name"));
      continue;
    }
    kept.push_back(std::move(entry));
  }
  ASSIGN_OR_RETURN(std::shared_ptr<const AccessPolicy> policy, BuildPolicy(kept));
  absl::MutexLock lock(&mutex_);
  stored_ = std::move(kept);
  install_(std::move(policy));
  return conflicts;
}

absl::StatusOr<IssuedToken> OperatorTokenService::Create(absl::string_view name, Role role) {
  RETURN_IF_ERROR(ValidateName(name));
  if (InFile(name)) {
    return absl::AlreadyExistsError(
        absl::StrCat("token '", name, "' exists (in the server's token file)"));
  }
  ASSIGN_OR_RETURN(std::string secret, RandomSecret());
  storage::StoredOperatorToken entry{{std::string(name), role, Sha256Hex(secret)},
                                     clock_->UnixMs()};
  absl::MutexLock lock(&mutex_);
  for (const storage::StoredOperatorToken& existing : stored_) {
    if (existing.token.name == name) {
      return absl::AlreadyExistsError(absl::StrCat("token '", name, "' exists"));
    }
  }
  std::vector<storage::StoredOperatorToken> next = stored_;
  next.push_back(entry);
  // The policy first: what it refuses is never stored.
  ASSIGN_OR_RETURN(std::shared_ptr<const AccessPolicy> policy, BuildPolicy(next));
  RETURN_IF_ERROR(store_->InsertToken(entry));
  stored_ = std::move(next);
  install_(std::move(policy));
  return IssuedToken{entry.token.name, role, std::move(secret), entry.created_unix_ms};
}

std::vector<TokenListing> OperatorTokenService::List() const {
  std::vector<TokenListing> out;
  for (const OperatorToken& token : file_tokens_) {
    out.push_back({token.name, token.role, TokenSource::kFile, 0});
  }
  std::vector<storage::StoredOperatorToken> stored;
  {
    absl::MutexLock lock(&mutex_);
    stored = stored_;
  }
  for (const storage::StoredOperatorToken& entry : stored) {
    out.push_back({entry.token.name, entry.token.role, TokenSource::kStore, entry.created_unix_ms});
  }
  std::stable_sort(out.begin(), out.end(), [](const TokenListing& a, const TokenListing& b) {
    if (a.source != b.source) return a.source == TokenSource::kFile;
    return a.name < b.name;
  });
  return out;
}

absl::Status OperatorTokenService::Revoke(absl::string_view name) {
  if (InFile(name)) {
    return absl::FailedPreconditionError(absl::StrCat(
        "token '", name, "' comes from the server's token file; remove it there and restart"));
  }
  absl::MutexLock lock(&mutex_);
  std::vector<storage::StoredOperatorToken> next;
  for (const storage::StoredOperatorToken& entry : stored_) {
    if (entry.token.name != name) next.push_back(entry);
  }
  if (next.size() == stored_.size()) {
    return absl::NotFoundError(absl::StrCat(
        "token '", EchoInput(std::string_view(name.data(), name.size())), "' not found"));
  }
  ASSIGN_OR_RETURN(std::shared_ptr<const AccessPolicy> policy, BuildPolicy(next));
  RETURN_IF_ERROR(store_->DeleteToken(std::string(name)));
  stored_ = std::move(next);
  install_(std::move(policy));
  return absl::OkStatus();
}

}  // namespace fleetnav::server
