#pragma once

#include <grpcpp/channel.h>
#include <grpcpp/security/credentials.h>

#include <memory>
#include <string>

namespace fleetnav::loadgen {

/// The fleetnavd a load run targets: its address and, for a TLS server, the folder that
/// deploy/certs/make-dev-certs wrote (server-ca.crt, robot-load-N.crt/.key per agent,
/// admin.token: the operators also store the site); plaintext when `tls_dir` is empty.
struct LoadTarget {
  std::string address;
  std::string tls_dir;
};

/// Credentials of agent `robot_id`: its own client certificate on TLS. Exits the process with a
/// message when a file is missing (a load run without its certificates is a setup error).
std::shared_ptr<grpc::ChannelCredentials> AgentCredentials(const LoadTarget& target,
                                                           const std::string& robot_id);
/// An operator's channel: on TLS the admin.token travels with every call.
std::shared_ptr<grpc::Channel> NewOperatorChannel(const LoadTarget& target, int index);

}  // namespace fleetnav::loadgen
