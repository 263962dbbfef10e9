#include "fleetnav/server/rpc/server_security.hpp"

#include <openssl/pem.h>
#include <openssl/x509.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <memory>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::server {
namespace {

absl::StatusOr<std::string> ReadFile(const std::string& path, const std::string& what) {
  if (path.empty()) return absl::InvalidArgumentError(absl::StrCat(what, ": no file given"));
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(absl::StrCat(what, ": cannot read '", path, "'"));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

using BioPtr = std::unique_ptr<BIO, decltype(&BIO_free)>;
using X509Ptr = std::unique_ptr<X509, decltype(&X509_free)>;
using KeyPtr = std::unique_ptr<EVP_PKEY, decltype(&EVP_PKEY_free)>;

BioPtr MemoryBio(const std::string& pem) {
  return BioPtr(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())), &BIO_free);
}

absl::StatusOr<X509Ptr> FirstCertificate(const std::string& pem, const std::string& path) {
  BioPtr bio = MemoryBio(pem);
  X509Ptr cert(PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr), &X509_free);
  if (cert == nullptr) {
    return absl::InvalidArgumentError(absl::StrCat("'", path, "' holds no PEM certificate"));
  }
  return cert;
}

absl::StatusOr<std::vector<OperatorToken>> TokensFromYaml(const YAML::Node& root) {
  if (!root.IsMap() || !root["tokens"] || !root["tokens"].IsSequence()) {
    return absl::InvalidArgumentError("tokens: expected `tokens: [{name, role, sha256}, ...]`");
  }
  std::vector<OperatorToken> tokens;
  int index = 0;
  for (const YAML::Node& entry : root["tokens"]) {
    const std::string where = absl::StrCat("tokens[", index++, "]");
    if (!entry.IsMap()) return absl::InvalidArgumentError(where + ": expected a mapping");
    for (const auto& key : entry) {
      const std::string name = key.first.as<std::string>();
      if (name != "name" && name != "role" && name != "sha256") {
        return absl::InvalidArgumentError(absl::StrCat(where, ": unknown key '", name, "'"));
      }
    }
    if (!entry["name"] || !entry["role"] || !entry["sha256"]) {
      return absl::InvalidArgumentError(where + ": needs name, role and sha256");
    }
    OperatorToken token;
    token.name = entry["name"].as<std::string>();
    absl::StatusOr<Role> role = ParseRole(entry["role"].as<std::string>());
    if (!role.ok())
      return absl::InvalidArgumentError(absl::StrCat(where, ": ", role.status().message()));
    token.role = *role;
    token.sha256_hex = entry["sha256"].as<std::string>();
    tokens.push_back(std::move(token));
  }
  // Tokens are made and revoked at run time by admins only: a file without one would leave
  // the site unmanageable until someone edits it and restarts (docs/security.md).
  if (std::none_of(tokens.begin(), tokens.end(),
                   [](const OperatorToken& token) { return token.role == Role::kAdmin; })) {
    return absl::InvalidArgumentError(
        "tokens: no token of role admin; the file needs at least the first admin, who makes "
        "the other tokens (docs/security.md)");
  }
  // The same checks the policy makes, so that a bad file is refused when it is loaded.
  if (absl::StatusOr<AccessPolicy> policy = AccessPolicy::Create(tokens); !policy.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("tokens: ", policy.status().message()));
  }
  return tokens;
}

}  // namespace

absl::StatusOr<std::vector<OperatorToken>> ParseOperatorTokens(absl::string_view yaml_text) {
  // yaml-cpp throws for text it cannot read and for a value of another shape (a key that is a
  // list, a name that is a map): both are the file's fault.
  try {
    return TokensFromYaml(YAML::Load(std::string(yaml_text)));
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat("tokens: ", e.what()));
  }
}

absl::StatusOr<ServerSecurity> LoadServerSecurity(const ServerSecurityFiles& files) {
  ServerSecurity security;
  ASSIGN_OR_RETURN(security.cert_chain_pem, ReadFile(files.cert_path, "tls cert"));
  ASSIGN_OR_RETURN(security.private_key_pem, ReadFile(files.key_path, "tls key"));
  ASSIGN_OR_RETURN(security.client_ca_pem, ReadFile(files.client_ca_path, "tls client CA"));
  ASSIGN_OR_RETURN(const std::string tokens_yaml, ReadFile(files.tokens_path, "tokens"));

  ASSIGN_OR_RETURN(X509Ptr cert, FirstCertificate(security.cert_chain_pem, files.cert_path));
  if (X509_cmp_current_time(X509_get0_notAfter(cert.get())) <= 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("'", files.cert_path, "': the server certificate has expired"));
  }
  BioPtr key_bio = MemoryBio(security.private_key_pem);
  KeyPtr key(PEM_read_bio_PrivateKey(key_bio.get(), nullptr, nullptr, nullptr), &EVP_PKEY_free);
  if (key == nullptr) {
    return absl::InvalidArgumentError(
        absl::StrCat("'", files.key_path, "' holds no PEM private key (or it is encrypted)"));
  }
  if (X509_check_private_key(cert.get(), key.get()) != 1) {
    return absl::InvalidArgumentError(absl::StrCat(
        "'", files.key_path, "' is not the key of the certificate '", files.cert_path, "'"));
  }
  RETURN_IF_ERROR(FirstCertificate(security.client_ca_pem, files.client_ca_path).status());
  absl::StatusOr<std::vector<OperatorToken>> tokens = ParseOperatorTokens(tokens_yaml);
  if (!tokens.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat(files.tokens_path, ": ", tokens.status().message()));
  }
  security.tokens = *std::move(tokens);
  return security;
}

}  // namespace fleetnav::server
