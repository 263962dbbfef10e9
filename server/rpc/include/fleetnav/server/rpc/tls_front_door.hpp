#pragma once

#include <grpcpp/server_builder.h>

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"

namespace fleetnav::server {

/// A TLS handshake gRPC refused, as gRPC's log gives it (OpenSSL's reason), turned into words.
/// "certificate verify failed" → "the client certificate did not verify against the robot CA
/// (another CA, expired or not yet valid)"; "wrong version number" → "not TLS (a plaintext
/// client?)"; any other reason as OpenSSL words it. nullopt for a line that is no server-side
/// handshake failure.
std::optional<std::string> HandshakeRefusalReason(const std::string& grpc_log_message);

struct TlsFrontDoorParams {
  /// host:port to listen on (port 0: any free port).
  std::string listen_address;
  /// Each refused handshake, as a status line naming the peer (fleetnavd's `refused:` log).
  std::function<void(const std::string&)> on_refusal;
  /// A connection that sends nothing for this long is closed without a word.
  double first_bytes_timeout_s = 120.0;
};

/// fleetnavd's own door to a TLS port, so that a refused TLS handshake is logged and counted
/// with its peer like any refused call: gRPC 1.51 reports a failed handshake only in its own
/// log and without the peer. The door binds the port itself and accepts every connection
/// (recording the peer), closes one whose first bytes are not a TLS handshake (a plaintext
/// client) and hands the others to gRPC (ServerBuilder's external connection acceptor) with the
/// server's TLS credentials. gRPC refuses a bad client certificate; its log line (GrpcLogTap)
/// is matched to the connection gRPC then closes, which the door watches through a duplicate of
/// the socket: gRPC logs the failure and shuts the socket on the same thread at once, so the
/// first handed-over connection to end after the report is the one refused. Thread-safe.
class TlsFrontDoor {
 public:
  explicit TlsFrontDoor(TlsFrontDoorParams params) : params_(std::move(params)) {}
  ~TlsFrontDoor();
  TlsFrontDoor(const TlsFrontDoor&) = delete;
  TlsFrontDoor& operator=(const TlsFrontDoor&) = delete;

  /// Binds and listens (InvalidArgument for a malformed address, Unavailable for one in use)
  /// and registers the door with `builder` for `credentials`; returns the bound port. Call
  /// before BuildAndStart, then Start.
  absl::StatusOr<int> Open(grpc::ServerBuilder* builder,
                           std::shared_ptr<grpc::ServerCredentials> credentials);
  /// Accepts connections from now on (the gRPC server must have started).
  void Start();
  /// Stops accepting and closes the port (before the gRPC server shuts down).
  void Stop();
  /// Handshakes refused so far (plaintext clients and certificates gRPC refused).
  uint64_t refused() const { return refused_.load(std::memory_order_relaxed); }

 private:
  struct Waiting {
    std::string peer;
    absl::Time accepted;
  };
  struct Report {
    std::string reason;
    absl::Time at;
  };
  void Loop();
  void Accept();
  void FirstBytes(int fd);
  void Ended(int watch_fd);
  void OnGrpcLog(const std::string& message);
  void MatchReports(absl::Time now);
  void Refuse(const std::string& peer, const std::string& reason);

  TlsFrontDoorParams params_;
  std::unique_ptr<grpc::experimental::ExternalConnectionAcceptor> acceptor_;
  int listen_fd_ = -1;
  int epoll_fd_ = -1;
  int wake_fd_ = -1;
  uint64_t log_subscription_ = 0;
  std::atomic<bool> stopping_{false};
  std::atomic<uint64_t> refused_{0};
  std::thread thread_;
  // The loop's own state (its thread only).
  std::map<int, Waiting> waiting_;     ///< accepted, first bytes not seen yet
  std::map<int, std::string> handed_;  ///< duplicate of a handed-over socket → its peer
  std::deque<std::string> ended_;      ///< peers of handed-over connections that just ended
  absl::Mutex reports_mutex_;
  std::deque<Report> reports_ ABSL_GUARDED_BY(reports_mutex_);
};

}  // namespace fleetnav::server
