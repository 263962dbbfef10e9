#include "fleetnav/server/rpc/access_gate.hpp"

#include "absl/strings/str_cat.h"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/server/rpc/replica_relay.hpp"

namespace fleetnav::server {
namespace {

absl::string_view Find(const grpc::AuthMetadataProcessor::InputMetadata& metadata,
                       absl::string_view key) {
  const auto found = metadata.find(grpc::string_ref(key.data(), key.size()));
  if (found == metadata.end()) return {};
  return {found->second.data(), found->second.size()};
}

bool Has(const grpc::AuthMetadataProcessor::InputMetadata& metadata, absl::string_view key) {
  return metadata.find(grpc::string_ref(key.data(), key.size())) != metadata.end();
}

}  // namespace

std::string CertificateIdentity(const grpc::AuthContext& context) {
  for (const grpc::string_ref& name : context.FindPropertyValues("x509_common_name")) {
    return {name.data(), name.size()};
  }
  return {};
}

grpc::Status AccessGate::Process(const InputMetadata& auth_metadata, grpc::AuthContext* context,
                                 OutputMetadata* consumed_auth_metadata,
                                 OutputMetadata* /*response_metadata*/) {
  CallerCredentials credentials;
  credentials.authorization = std::string(Find(auth_metadata, "authorization"));
  credentials.certificate_identity = CertificateIdentity(*context);
  const absl::string_view method = Find(auth_metadata, ":path");
  if (Has(auth_metadata, kRelayKeyHeader) || Has(auth_metadata, kRelayedRobotHeader)) {
    const absl::string_view key = Find(auth_metadata, kRelayKeyHeader);
    if (!IsReplicaRelayKey(key, relay_key_)) {
      const absl::Status refused = absl::UnauthenticatedError(absl::StrCat(
          method, relay_key_.empty() ? ": a relayed call, but this server takes none"
                                     : ": a relayed call without the replicas' relay key"));
      control_->Refused(refused);
      return ToGrpcStatus(refused);
    }
    // Relayed by a replica: the connection is the replica's, the certificate the one it
    // verified on the caller's connection.
    credentials.certificate_identity = std::string(Find(auth_metadata, kRelayedRobotHeader));
    consumed_auth_metadata->emplace(kRelayKeyHeader, std::string(key));
  }
  return ToGrpcStatus(control_->Authorize(method, credentials).status());
}

absl::Status AccessGate::CheckRobotClaim(const grpc::ServerContextBase& call,
                                         absl::string_view robot_id) {
  // Process refused every call with this header and no relay key, so one here is vouched for.
  const auto& metadata = call.client_metadata();
  const auto relayed = metadata.find(kRelayedRobotHeader);
  std::string identity;
  if (relayed != metadata.end()) {
    identity.assign(relayed->second.data(), relayed->second.size());
  } else if (const std::shared_ptr<const grpc::AuthContext> context = call.auth_context();
             context != nullptr) {
    identity = CertificateIdentity(*context);
  }
  if (identity == robot_id) return absl::OkStatus();
  const absl::Status denied = absl::PermissionDeniedError(
      absl::StrCat("hello: this stream's certificate is robot '", identity,
                   "'; it cannot speak for robot '", robot_id, "'"));
  control_->Refused(denied);
  return denied;
}

}  // namespace fleetnav::server
