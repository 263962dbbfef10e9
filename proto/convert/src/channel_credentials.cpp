#include "fleetnav/proto/channel_credentials.hpp"

#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"

namespace fleetnav {
namespace {

absl::StatusOr<std::string> ReadPem(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(absl::StrCat(what, ": cannot read '", path, "'"));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> MakeChannelCredentials(
    const ClientTlsFiles& files) {
  if (files.cert_path.empty() != files.key_path.empty()) {
    return absl::InvalidArgumentError(
        "a client certificate needs its key and a key its certificate (--tls-cert with --tls-key)");
  }
  if (!files.secure()) {
    if (!files.cert_path.empty()) {
      return absl::InvalidArgumentError(
          "a client certificate needs the server's CA too (--tls-ca)");
    }
    return grpc::InsecureChannelCredentials();
  }
  grpc::SslCredentialsOptions options;
  absl::StatusOr<std::string> ca = ReadPem(files.ca_path, "tls CA");
  if (!ca.ok()) return ca.status();
  options.pem_root_certs = *std::move(ca);
  if (!files.cert_path.empty()) {
    absl::StatusOr<std::string> cert = ReadPem(files.cert_path, "tls cert");
    if (!cert.ok()) return cert.status();
    absl::StatusOr<std::string> key = ReadPem(files.key_path, "tls key");
    if (!key.ok()) return key.status();
    options.pem_cert_chain = *std::move(cert);
    options.pem_private_key = *std::move(key);
  }
  return grpc::SslCredentials(options);
}

void AddTlsChannelArguments(const ClientTlsFiles& files, grpc::ChannelArguments* arguments) {
  if (files.secure() && !files.server_name.empty()) {
    arguments->SetSslTargetNameOverride(files.server_name);
  }
}

}  // namespace fleetnav
