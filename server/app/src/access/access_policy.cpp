#include "fleetnav/server/access/access_policy.hpp"

#include <openssl/evp.h>

#include <array>

#include "absl/container/flat_hash_set.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"

namespace fleetnav::server {
namespace {

/// Who may call a method.
enum class Requirement {
  kOpen,         ///< anyone, without credentials
  kRobotStream,  ///< a robot's certificate
  kSiteRead,     ///< a robot's certificate or a viewer's token
  kViewer,
  kOperator,
  kAdmin,
};

struct MethodRule {
  absl::string_view method;
  Requirement requirement;
};

constexpr absl::string_view kFleet = "/fleetnav.v1.FleetService/";
constexpr absl::string_view kHttpRead = "/fleetnav.http/Read";
constexpr absl::string_view kHttpAct = "/fleetnav.http/Act";

// Every RPC fleetnavd serves; a method not listed is refused (tests call every method of the
// services' descriptors, so a new RPC without a rule fails them).
constexpr std::array kRules = {
    MethodRule{"/grpc.health.v1.Health/Check", Requirement::kOpen},
    MethodRule{"/grpc.health.v1.Health/Watch", Requirement::kOpen},
    MethodRule{"/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo",
               Requirement::kViewer},
    MethodRule{"/fleetnav.v1.AgentService/Connect", Requirement::kRobotStream},
    // The HTTP port (dashboard, /metrics): reads, and the dashboard's job buttons.
    MethodRule{kHttpRead, Requirement::kViewer},
    MethodRule{kHttpAct, Requirement::kOperator},
    MethodRule{"GetMap", Requirement::kSiteRead},
    MethodRule{"ListMaps", Requirement::kSiteRead},
    MethodRule{"GetMarkerSet", Requirement::kSiteRead},
    MethodRule{"GetZones", Requirement::kSiteRead},
    MethodRule{"ListZones", Requirement::kSiteRead},
    MethodRule{"GetRoute", Requirement::kSiteRead},
    MethodRule{"ListRoutes", Requirement::kSiteRead},
    MethodRule{"ListRobots", Requirement::kViewer},
    MethodRule{"GetRobot", Requirement::kViewer},
    MethodRule{"WatchFleet", Requirement::kViewer},
    MethodRule{"GetJob", Requirement::kViewer},
    MethodRule{"ListJobs", Requirement::kViewer},
    MethodRule{"WatchJob", Requirement::kViewer},
    MethodRule{"PlanPaths", Requirement::kViewer},
    MethodRule{"SubmitJob", Requirement::kOperator},
    MethodRule{"CancelJob", Requirement::kOperator},
    MethodRule{"PauseJob", Requirement::kOperator},
    MethodRule{"ResumeJob", Requirement::kOperator},
    MethodRule{"StopRobots", Requirement::kOperator},
    MethodRule{"ResumeRobots", Requirement::kOperator},
    MethodRule{"ListStops", Requirement::kViewer},
    MethodRule{"PutMap", Requirement::kAdmin},
    MethodRule{"DeleteMap", Requirement::kAdmin},
    MethodRule{"PutMarkerSet", Requirement::kAdmin},
    MethodRule{"DeleteMarkerSet", Requirement::kAdmin},
    MethodRule{"PutZones", Requirement::kAdmin},
    MethodRule{"DeleteZones", Requirement::kAdmin},
    MethodRule{"PutRoute", Requirement::kAdmin},
    MethodRule{"DeleteRoute", Requirement::kAdmin},
    MethodRule{"ForgetRobot", Requirement::kAdmin},
    // Operator tokens themselves.
    MethodRule{"/fleetnav.v1.AccessService/CreateToken", Requirement::kAdmin},
    MethodRule{"/fleetnav.v1.AccessService/ListTokens", Requirement::kAdmin},
    MethodRule{"/fleetnav.v1.AccessService/RevokeToken", Requirement::kAdmin},
};

/// The rule of a method; rules without a leading '/' are FleetService methods.
const MethodRule* FindRule(absl::string_view method) {
  for (const MethodRule& rule : kRules) {
    if (rule.method.front() == '/') {
      if (method == rule.method) return &rule;
    } else if (absl::StartsWith(method, kFleet) && method.substr(kFleet.size()) == rule.method) {
      return &rule;
    }
  }
  return nullptr;
}

bool IsLowerHex(absl::string_view text) {
  for (char c : text) {
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  }
  return true;
}

}  // namespace

std::string Sha256Hex(absl::string_view text) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  EVP_Digest(text.data(), text.size(), digest.data(), &length, EVP_sha256(), nullptr);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(2 * length);
  for (unsigned int i = 0; i < length; ++i) {
    hex.push_back(kHex[digest[i] >> 4]);
    hex.push_back(kHex[digest[i] & 0xf]);
  }
  return hex;
}

absl::StatusOr<AccessPolicy> AccessPolicy::Create(std::vector<OperatorToken> tokens) {
  AccessPolicy policy;
  absl::flat_hash_set<std::string> names;
  for (OperatorToken& token : tokens) {
    if (token.name.empty()) return absl::InvalidArgumentError("a token without a name");
    if (token.sha256_hex.size() != 64 || !IsLowerHex(token.sha256_hex)) {
      return absl::InvalidArgumentError(
          absl::StrCat("token '", token.name,
                       "': sha256 must be 64 lower-case hex digits (sha256sum of the token)"));
    }
    if (!names.insert(token.name).second) {
      return absl::InvalidArgumentError(absl::StrCat("token name '", token.name, "' given twice"));
    }
    const std::string name = token.name;
    std::string hash = token.sha256_hex;
    if (!policy.by_hash_.emplace(std::move(hash), std::move(token)).second) {
      return absl::InvalidArgumentError(
          absl::StrCat("two tokens share one hash (the second is '", name, "')"));
    }
  }
  return policy;
}

absl::StatusOr<Caller> AccessPolicy::Authorize(absl::string_view method,
                                               const CallerCredentials& credentials) const {
  const MethodRule* rule = FindRule(method);
  if (rule == nullptr) {
    return absl::PermissionDeniedError(absl::StrCat(method, ": no caller may call this method"));
  }
  switch (rule->requirement) {
    case Requirement::kOpen:
      return Caller{"anyone", false, Role::kViewer};
    case Requirement::kRobotStream:
      if (credentials.certificate_identity.empty()) {
        return absl::UnauthenticatedError(
            absl::StrCat(method, ": needs a robot's client certificate signed by the robot CA"));
      }
      return Caller{credentials.certificate_identity, true, Role::kViewer};
    case Requirement::kSiteRead:
      if (credentials.authorization.empty() && !credentials.certificate_identity.empty()) {
        return Caller{credentials.certificate_identity, true, Role::kViewer};
      }
      return AuthorizeOperator(method, Role::kViewer, credentials);
    case Requirement::kViewer:
      return AuthorizeOperator(method, Role::kViewer, credentials);
    case Requirement::kOperator:
      return AuthorizeOperator(method, Role::kOperator, credentials);
    case Requirement::kAdmin:
      return AuthorizeOperator(method, Role::kAdmin, credentials);
  }
  return absl::PermissionDeniedError(absl::StrCat(method, ": refused"));
}

absl::StatusOr<Caller> AccessPolicy::AuthorizeOperator(absl::string_view method, Role needed,
                                                       const CallerCredentials& credentials) const {
  if (credentials.authorization.empty()) {
    return absl::UnauthenticatedError(
        absl::StrCat(method, ": needs an operator token (authorization: Bearer TOKEN) of role ",
                     RoleName(needed), " or above"));
  }
  // RFC 7235: the scheme is case-insensitive; RFC 6750: one or more spaces before the token.
  absl::string_view token = credentials.authorization;
  constexpr absl::string_view kScheme = "bearer";
  const bool bearer = token.size() > kScheme.size() &&
                      absl::EqualsIgnoreCase(token.substr(0, kScheme.size()), kScheme) &&
                      token[kScheme.size()] == ' ';
  if (bearer) {
    token.remove_prefix(kScheme.size());
    while (!token.empty() && token.front() == ' ') token.remove_prefix(1);
  }
  if (!bearer || token.empty()) {
    return absl::UnauthenticatedError(
        absl::StrCat(method, ": malformed authorization header (expected 'Bearer TOKEN')"));
  }
  const auto found = by_hash_.find(Sha256Hex(token));
  if (found == by_hash_.end()) {
    return absl::UnauthenticatedError(absl::StrCat(method, ": unknown token"));
  }
  const OperatorToken& holder = found->second;
  if (static_cast<int>(holder.role) < static_cast<int>(needed)) {
    return absl::PermissionDeniedError(absl::StrCat(method, ": token '", holder.name, "' has role ",
                                                    RoleName(holder.role), ", the method needs ",
                                                    RoleName(needed)));
  }
  return Caller{holder.name, false, holder.role};
}

}  // namespace fleetnav::server
