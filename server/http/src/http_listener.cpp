#include "http_listener.hpp"

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"

namespace fleetnav::server::http {

absl::Status ValidateHttpListen(const std::string& listen_address, const std::string& cert_path,
                                const std::string& key_path, int threads) {
  const size_t colon = listen_address.rfind(':');
  int port = 0;
  if (colon == std::string::npos || colon == 0 ||
      !absl::SimpleAtoi(listen_address.substr(colon + 1), &port) || port < 0 || port > 65535) {
    return absl::InvalidArgumentError(
        absl::StrCat("http listen address '", listen_address, "': expected host:port"));
  }
  if (cert_path.empty() != key_path.empty()) {
    return absl::InvalidArgumentError("http: a TLS certificate needs its key");
  }
  if (threads < 2 || threads > 256) {
    return absl::InvalidArgumentError(
        absl::StrCat("http threads: must be in [2, 256], got ", threads));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::unique_ptr<httplib::Server>> MakeHttpServer(const std::string& cert_path,
                                                                const std::string& key_path,
                                                                size_t max_request_bytes,
                                                                int threads) {
  std::unique_ptr<httplib::Server> server;
  if (cert_path.empty()) {
    server = std::make_unique<httplib::Server>();
  } else {
    auto https = std::make_unique<httplib::SSLServer>(cert_path.c_str(), key_path.c_str());
    if (!https->is_valid()) {
      return absl::InvalidArgumentError(absl::StrCat("http: cannot use the certificate '",
                                                     cert_path, "' with key '", key_path, "'"));
    }
    server = std::move(https);
  }
  server->set_payload_max_length(max_request_bytes);
  const auto pool_size = static_cast<size_t>(threads);
  server->new_task_queue = [pool_size] { return new httplib::ThreadPool(pool_size); };
  server->set_read_timeout(5, 0);
  return server;
}

absl::StatusOr<int> BindHttpServer(httplib::Server* server, const std::string& listen_address) {
  const size_t colon = listen_address.rfind(':');
  const std::string host = listen_address.substr(0, colon);
  int port = 0;
  (void)absl::SimpleAtoi(listen_address.substr(colon + 1), &port);
  const int bound =
      port == 0 ? server->bind_to_any_port(host) : (server->bind_to_port(host, port) ? port : -1);
  if (bound <= 0) {
    return absl::UnavailableError(absl::StrCat("http: cannot listen on ", listen_address,
                                               ": already in use or not available"));
  }
  return bound;
}

}  // namespace fleetnav::server::http
