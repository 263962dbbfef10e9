#pragma once

#include <functional>
#include <string>

#include "fleetnav/server/access/operator_tokens.hpp"
#include "fleetnav/v1/access_service.grpc.pb.h"

namespace fleetnav::server {

/// fleetnav.v1.AccessService: the wire edge of OperatorTokenService (the AccessPolicy admits
/// only admins). Each token created or revoked is reported to `on_change` for the log, by name
/// and role, never with its secret. Thread-safe.
class AccessServiceImpl final : public v1::AccessService::Service {
 public:
  AccessServiceImpl(OperatorTokenService* tokens, std::function<void(const std::string&)> on_change)
      : tokens_(tokens), on_change_(std::move(on_change)) {}

  grpc::Status CreateToken(grpc::ServerContext* context, const v1::CreateTokenRequest* request,
                           v1::CreateTokenResponse* response) override;
  grpc::Status ListTokens(grpc::ServerContext* context, const v1::ListTokensRequest* request,
                          v1::ListTokensResponse* response) override;
  grpc::Status RevokeToken(grpc::ServerContext* context, const v1::RevokeTokenRequest* request,
                           v1::RevokeTokenResponse* response) override;

 private:
  void Report(const std::string& what) const {
    if (on_change_) on_change_(what);
  }

  OperatorTokenService* tokens_;
  std::function<void(const std::string&)> on_change_;
};

}  // namespace fleetnav::server
