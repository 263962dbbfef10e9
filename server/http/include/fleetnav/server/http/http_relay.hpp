#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "absl/status/statusor.h"

namespace httplib {
class Server;
struct Request;
struct Response;
}  // namespace httplib

namespace fleetnav::server::http {

struct HttpRelayParams {
  std::string listen_address;  ///< host:port; port 0 picks a free one
  /// HTTPS with these (the replicas' TLS certificate and key); plain HTTP when empty.
  std::string cert_path;
  std::string key_path;
  /// The leader's dashboard is reached over HTTPS trusting only the certificates in this file
  /// (the replicas' own certificate, pinned: no CA is asked); plain HTTP when empty.
  std::string upstream_ca_path;
  size_t max_request_bytes = 64 * 1024;  ///< larger bodies: 413
  /// Requests relayed at once; each open dashboard holds one for its event stream.
  int threads = 16;
  /// Connecting to the leader, and each read from it, may take this long before the request
  /// fails 502.
  double upstream_timeout_s = 10.0;
  absl::Status Validate() const;
};

/// The HTTP port of a fleetnavd replica (`--replica --http-listen`): relays every request (the
/// dashboard, its API and event stream, its buttons, /metrics) to the dashboard of the site's
/// leader (an HttpGateway over the leader's FleetServer), with the caller's `Authorization`
/// header, and answers with the leader's status, type and body; an event stream is passed on
/// as it comes. The leader checks the token with its live AccessPolicy, so tokens made or
/// revoked at run time hold on every replica. `/healthz` is answered here (this replica is up).
/// While no leader is known a request fails 503, when the leader cannot be reached 502; the
/// dashboard then retries. On HTTPS it reaches the leader over HTTPS, trusting only the pinned
/// certificate. Start once; Stop ends the streams and joins the listener. Thread-safe
/// (cpp-httplib's worker threads, one reader thread per request relayed).
class HttpRelay {
 public:
  /// `leader` returns the leader dashboard's host:port now, or "" while none is known; it is
  /// called for every request and must be quick.
  HttpRelay(std::function<std::string()> leader, HttpRelayParams params);
  ~HttpRelay();
  HttpRelay(const HttpRelay&) = delete;
  HttpRelay& operator=(const HttpRelay&) = delete;

  /// Binds and starts serving; returns the bound port. InvalidArgument for bad parameters or
  /// unusable certificate files, Unavailable when the address cannot be bound.
  absl::StatusOr<int> Start();
  void Stop();

 private:
  void Relay(const httplib::Request& req, httplib::Response& res);

  std::function<std::string()> leader_;
  HttpRelayParams params_;
  std::unique_ptr<httplib::Server> http_;
  std::thread listener_;
  std::atomic<bool> stopping_{false};
};

}  // namespace fleetnav::server::http
