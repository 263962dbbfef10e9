#include "fleetnav/server/rpc/access_service.hpp"

#include "absl/strings/str_cat.h"
#include "fleetnav/proto/access_convert.hpp"
#include "fleetnav/proto/grpc_status.hpp"

namespace fleetnav::server {

grpc::Status AccessServiceImpl::CreateToken(grpc::ServerContext*,
                                            const v1::CreateTokenRequest* request,
                                            v1::CreateTokenResponse* response) {
  absl::StatusOr<Role> role = FromProto(request->role());
  if (!role.ok()) return ToGrpcStatus(role.status());
  absl::StatusOr<IssuedToken> issued = tokens_->Create(request->name(), *role);
  if (!issued.ok()) return ToGrpcStatus(issued.status());
  response->set_name(issued->name);
  response->set_role(ToProto(issued->role));
  response->set_token(issued->secret);
  response->set_created_unix_ms(issued->created_unix_ms);
  Report(absl::StrCat("token '", issued->name, "' (", RoleName(issued->role), ") created"));
  return grpc::Status::OK;
}

grpc::Status AccessServiceImpl::ListTokens(grpc::ServerContext*, const v1::ListTokensRequest*,
                                           v1::ListTokensResponse* response) {
  for (const TokenListing& listing : tokens_->List()) {
    v1::TokenInfo* info = response->add_tokens();
    info->set_name(listing.name);
    info->set_role(ToProto(listing.role));
    info->set_source(std::string(TokenSourceName(listing.source)));
    info->set_created_unix_ms(listing.created_unix_ms);
  }
  return grpc::Status::OK;
}

grpc::Status AccessServiceImpl::RevokeToken(grpc::ServerContext*,
                                            const v1::RevokeTokenRequest* request,
                                            v1::RevokeTokenResponse*) {
  const absl::Status revoked = tokens_->Revoke(request->name());
  if (!revoked.ok()) return ToGrpcStatus(revoked);
  Report(absl::StrCat("token '", request->name(), "' revoked"));
  return grpc::Status::OK;
}

}  // namespace fleetnav::server
