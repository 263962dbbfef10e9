#pragma once

#include <httplib.h>

#include <cstddef>
#include <memory>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace fleetnav::server::http {

/// InvalidArgument unless `listen_address` is host:port (port 0: any), a certificate comes
/// with its key, and `threads` is in [2, 256]: what the dashboard gateway and a replica's relay
/// both check.
absl::Status ValidateHttpListen(const std::string& listen_address, const std::string& cert_path,
                                const std::string& key_path, int threads);

/// An HTTP server, or HTTPS with the certificate and key (InvalidArgument when they do not
/// go together), taking requests up to `max_request_bytes` on `threads` worker threads.
absl::StatusOr<std::unique_ptr<httplib::Server>> MakeHttpServer(const std::string& cert_path,
                                                                const std::string& key_path,
                                                                size_t max_request_bytes,
                                                                int threads);

/// Binds `server` to the validated `listen_address`; returns the port (Unavailable when taken).
absl::StatusOr<int> BindHttpServer(httplib::Server* server, const std::string& listen_address);

}  // namespace fleetnav::server::http
