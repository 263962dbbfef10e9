#pragma once

#include <grpcpp/security/credentials.h>
#include <grpcpp/support/channel_arguments.h>

#include <memory>
#include <string>

#include "absl/status/statusor.h"

namespace fleetnav {

/// How a client reaches fleetnavd: plaintext when `ca_path` is empty, else TLS trusting that
/// CA, with a client certificate when `cert_path` and `key_path` are given (robots; the
/// certificate's common name is the robot id).
struct ClientTlsFiles {
  std::string ca_path;
  std::string cert_path;
  std::string key_path;
  /// The name the server's certificate must carry when it differs from the dialled host
  /// (e.g. dialling an IP address of a server whose certificate names its host).
  std::string server_name;

  bool secure() const { return !ca_path.empty(); }
};

/// Reads the files and builds channel credentials. NotFound naming an unreadable file;
/// InvalidArgument when a certificate is given without its key (or the other way round), or
/// a client certificate without a CA.
absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> MakeChannelCredentials(
    const ClientTlsFiles& files);

/// Adds what `files` needs to a channel's arguments (the server-name override).
void AddTlsChannelArguments(const ClientTlsFiles& files, grpc::ChannelArguments* arguments);

}  // namespace fleetnav
