#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/server/fleet_app.hpp"

namespace httplib {
class Server;
}

namespace fleetnav::server::http {

struct HttpGatewayParams {
  std::string listen_address;  ///< host:port; port 0 picks a free one
  /// HTTPS with these (fleetnavd passes its own TLS certificate and key); plain HTTP when empty.
  std::string cert_path;
  std::string key_path;
  double push_rate_hz = 5.0;             ///< dashboard updates per second
  size_t max_request_bytes = 64 * 1024;  ///< larger bodies: 413
  /// Requests served at once; each open dashboard holds one for its event stream.
  int threads = 16;
  absl::Status Validate() const;
};

/// fleetnavd's HTTP port (`--http-listen`): the live web dashboard (its assets compiled into the
/// binary), its JSON API with updates pushed as server-sent events, the dashboard's pause,
/// resume and cancel buttons, `/metrics` for Prometheus and `/healthz`. On a TLS server it
/// serves HTTPS and every request but `/healthz` and the static assets needs a bearer token:
/// reads a viewer's, the buttons an operator's (the app's AccessControl, as for RPCs). Unknown
/// paths are 404, oversized requests 413; nothing is read from the file system. Start once; Stop
/// ends the event streams and joins the listener. Thread-safe (cpp-httplib's worker threads).
class HttpGateway {
 public:
  /// Serves `app` (which outlives the gateway); `render_metrics` gives `/metrics`' text.
  HttpGateway(FleetApp* app, std::function<std::string()> render_metrics, HttpGatewayParams params);
  ~HttpGateway();
  HttpGateway(const HttpGateway&) = delete;
  HttpGateway& operator=(const HttpGateway&) = delete;

  /// Binds and starts serving; returns the bound port. InvalidArgument for bad parameters or
  /// unreadable certificate files, Unavailable when the address cannot be bound.
  absl::StatusOr<int> Start();
  void Stop();

 private:
  void AddHandlers();
  /// The state document the dashboard draws (FleetStateJson).
  std::string StateJson();
  /// The unfinished jobs, read from the store only when a job changed since the last read.
  std::vector<Job> UnfinishedJobs();
  /// The operators' stops in force, read again only after a stop was made or cleared.
  std::vector<RobotStop> StopsInForce();

  FleetApp* app_;
  std::function<std::string()> render_metrics_;
  HttpGatewayParams params_;
  std::unique_ptr<httplib::Server> http_;
  std::thread listener_;
  std::atomic<bool> stopping_{false};
  absl::Mutex jobs_mutex_;
  uint64_t jobs_read_at_ ABSL_GUARDED_BY(jobs_mutex_) = ~uint64_t{0};  ///< job_changes() then
  std::vector<Job> unfinished_jobs_ ABSL_GUARDED_BY(jobs_mutex_);
  uint64_t stops_read_at_ ABSL_GUARDED_BY(jobs_mutex_) = ~uint64_t{0};  ///< stop_changes() then
  std::vector<RobotStop> stops_ ABSL_GUARDED_BY(jobs_mutex_);
};

}  // namespace fleetnav::server::http
