#pragma once

#include <string>
#include <string_view>

#include "absl/status/statusor.h"
#include "fleetnav/server/rpc/fleet_server.hpp"

namespace fleetnav::server {

/// fleetnavd's YAML configuration (see docs/server.md); every key is optional:
///   listen: 0.0.0.0:50051
///   db: /var/lib/fleetnav/fleet.db
///   log_level: info                # trace | debug | info | warn | error
///   tls: {cert: server.crt, key: server.key, client_ca: robot-ca.crt, tokens: tokens.yaml}
///   insecure: false                # true: plaintext, no authentication (instead of tls)
///   limits: {max_message_bytes: 67108864, max_page_size: 1000}
///   timeouts: {stale_after_s: 2.0, lost_robot_timeout_s: 30.0, dispatch_period_s: 0.2}
///   charging: {below_fraction: 0.2, charged_fraction: 0.9, routes: {barn: barn-charge}}
/// Unknown keys and bad values are InvalidArgument naming the key; the result is validated.
struct FleetServerConfig {
  FleetServerParams params;
  std::string log_level = "info";
  /// Serve plaintext without authentication; fleetnavd refuses to start with neither this nor
  /// the tls files.
  bool insecure = false;
};

absl::StatusOr<FleetServerConfig> ParseFleetServerConfig(std::string_view yaml_text,
                                                         FleetServerConfig defaults = {});
absl::StatusOr<FleetServerConfig> LoadFleetServerConfig(const std::string& path,
                                                        FleetServerConfig defaults = {});

}  // namespace fleetnav::server
