#include "load_tls.hpp"

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>

#include <cstdlib>
#include <fstream>
#include <iostream>

#include "fleetnav/proto/channel_credentials.hpp"

namespace fleetnav::loadgen {
namespace {

std::shared_ptr<grpc::ChannelCredentials> OrExit(
    absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> credentials) {
  if (!credentials.ok()) {
    std::cerr << "fleetnav-loadgen: " << credentials.status().message() << '\n';
    std::exit(2);
  }
  return *std::move(credentials);
}

/// Adds `authorization: Bearer TOKEN` to every call of a channel.
class BearerToken final : public grpc::MetadataCredentialsPlugin {
 public:
  explicit BearerToken(std::string token) : header_("Bearer " + std::move(token)) {}
  bool IsBlocking() const override { return false; }
  grpc::Status GetMetadata(grpc::string_ref, grpc::string_ref, const grpc::AuthContext&,
                           std::multimap<grpc::string, grpc::string>* metadata) override {
    metadata->emplace("authorization", header_);
    return grpc::Status::OK;
  }

 private:
  std::string header_;
};

}  // namespace

std::shared_ptr<grpc::ChannelCredentials> AgentCredentials(const LoadTarget& target,
                                                           const std::string& robot_id) {
  if (target.tls_dir.empty()) return grpc::InsecureChannelCredentials();
  ClientTlsFiles files;
  files.ca_path = target.tls_dir + "/server-ca.crt";
  files.cert_path = target.tls_dir + "/robot-" + robot_id + ".crt";
  files.key_path = target.tls_dir + "/robot-" + robot_id + ".key";
  return OrExit(MakeChannelCredentials(files));
}

std::shared_ptr<grpc::Channel> NewOperatorChannel(const LoadTarget& target, int index) {
  grpc::ChannelArguments args;
  args.SetMaxSendMessageSize(64 << 20);                // the big map
  args.SetInt(GRPC_ARG_ENABLE_RETRIES, 0);             // no retry buffering on long streams
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);  // one connection per channel
  args.SetInt("fleetnav.loadgen.channel", index);
  // A list of replicas: spread the calls over them.
  if (target.address.rfind("ipv4:", 0) == 0 || target.address.rfind("ipv6:", 0) == 0) {
    args.SetLoadBalancingPolicyName("round_robin");
  }
  if (target.tls_dir.empty()) {
    return grpc::CreateCustomChannel(target.address, grpc::InsecureChannelCredentials(), args);
  }
  ClientTlsFiles files;
  files.ca_path = target.tls_dir + "/server-ca.crt";
  std::ifstream token_file(target.tls_dir + "/admin.token");
  std::string token;
  if (!std::getline(token_file, token) || token.empty()) {
    std::cerr << "fleetnav-loadgen: cannot read " << target.tls_dir << "/admin.token\n";
    std::exit(2);
  }
  auto credentials = grpc::CompositeChannelCredentials(
      OrExit(MakeChannelCredentials(files)),
      grpc::MetadataCredentialsFromPlugin(std::make_unique<BearerToken>(token)));
  return grpc::CreateCustomChannel(target.address, credentials, args);
}

}  // namespace fleetnav::loadgen
