#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace fleetnav::server {

/// A view of gRPC's own log for the parts of fleetnavd that need what only gRPC's log says (a
/// TLS handshake that failed inside gRPC). gRPC has one log function per process
/// (gpr_set_log_function), so the tap is process-wide state, like ODE's and mosquitto's
/// initialisation: the first subscription installs it, and from then on every message gRPC
/// logs at ERROR and above reaches the subscribers, and every message reaches gRPC's default log
/// exactly as GRPC_VERBOSITY asks (so the tap changes nothing an operator sees). Thread-safe;
/// subscribers run on gRPC's threads and must not block or log through gRPC.
class GrpcLogTap {
 public:
  using Listener = std::function<void(const std::string& message)>;
  /// Calls `listener` with each ERROR message until Unsubscribe(the returned id).
  static uint64_t Subscribe(Listener listener);
  static void Unsubscribe(uint64_t id);
};

}  // namespace fleetnav::server
