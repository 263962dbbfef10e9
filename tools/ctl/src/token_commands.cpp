#include <grpcpp/client_context.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "absl/strings/str_cat.h"
#include "absl/time/time.h"
#include "call_internal.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/ctl/commands.hpp"
#include "fleetnav/ctl/table.hpp"
#include "fleetnav/proto/access_convert.hpp"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/v1/access_service.grpc.pb.h"

namespace fleetnav::ctl {
namespace {

std::string RoleText(v1::OperatorRole role) {
  absl::StatusOr<Role> parsed = FromProto(role);
  return parsed.ok() ? std::string(RoleName(*parsed)) : "unknown";
}

std::string CreatedText(int64_t created_unix_ms) {
  if (created_unix_ms == 0) return "-";
  return absl::FormatTime("%Y-%m-%d %H:%M:%S UTC", absl::FromUnixMillis(created_unix_ms),
                          absl::UTCTimeZone());
}

}  // namespace

absl::Status CreateToken(const CommandContext& context, const std::string& name,
                         const std::string& role_name) {
  ASSIGN_OR_RETURN(const Role role, ParseRole(role_name));
  v1::CreateTokenRequest request;
  request.set_name(name);
  request.set_role(ToProto(role));
  v1::CreateTokenResponse response;
  auto stub = v1::AccessService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  RETURN_IF_ERROR(FromGrpcStatus(stub->CreateToken(&rpc, request, &response)));
  if (context.json) {
    *context.out << nlohmann::json{{"name", response.name()},
                                   {"role", RoleText(response.role())},
                                   {"token", response.token()},
                                   {"created_unix_ms", response.created_unix_ms()}}
                        .dump()
                 << '\n';
  } else {
    // The secret alone on stdout (`fleetnavctl tokens create ... > night.token`); the note on
    // stderr, since it is shown only this once.
    *context.out << response.token() << '\n';
    std::cerr << "fleetnavctl: token '" << response.name() << "' (" << RoleText(response.role())
              << ") created; the server keeps only its hash, so store it now\n";
  }
  return absl::OkStatus();
}

absl::Status ListTokens(const CommandContext& context) {
  auto stub = v1::AccessService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  v1::ListTokensResponse response;
  RETURN_IF_ERROR(FromGrpcStatus(stub->ListTokens(&rpc, {}, &response)));
  if (context.json) {
    nlohmann::json tokens = nlohmann::json::array();
    for (const v1::TokenInfo& token : response.tokens()) {
      tokens.push_back({{"name", token.name()},
                        {"role", RoleText(token.role())},
                        {"source", token.source()},
                        {"created_unix_ms", token.created_unix_ms()}});
    }
    *context.out << tokens.dump() << '\n';
    return absl::OkStatus();
  }
  Table table({"NAME", "ROLE", "SOURCE", "CREATED"});
  for (const v1::TokenInfo& token : response.tokens()) {
    table.AddRow({token.name(), RoleText(token.role()), token.source(),
                  CreatedText(token.created_unix_ms())});
  }
  table.Print(*context.out);
  return absl::OkStatus();
}

absl::Status RevokeToken(const CommandContext& context, const std::string& name) {
  v1::RevokeTokenRequest request;
  request.set_name(name);
  v1::RevokeTokenResponse response;
  auto stub = v1::AccessService::NewStub(context.channel);
  grpc::ClientContext rpc;
  PrepareCall(context, &rpc);
  RETURN_IF_ERROR(FromGrpcStatus(stub->RevokeToken(&rpc, request, &response)));
  *context.out << (context.json ? nlohmann::json{{"revoked", name}}.dump()
                                : absl::StrCat("revoked token '", name, "'"))
               << '\n';
  return absl::OkStatus();
}

}  // namespace fleetnav::ctl
