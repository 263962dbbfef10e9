#pragma once

#include <cstdint>
#include <memory>
#include <ostream>
#include <string>

#include <grpcpp/channel.h>

#include "absl/status/status.h"

namespace fleetnav::ctl {

/// What every fleetnavctl command needs: the server channel, the output stream, the format.
struct CommandContext {
  std::shared_ptr<grpc::Channel> channel;
  std::ostream* out = nullptr;
  bool json = false;
  double timeout_s = 10.0;
};

/// Uploads a ROS map_server map (YAML and the PGM it names) as a new version of `map_id`.
absl::Status ImportMap(const CommandContext& context, const std::string& map_id,
                       const std::string& yaml_path, const std::string& description);
/// Lists the latest version of every map.
absl::Status ListMaps(const CommandContext& context);
/// Downloads a map version (0 = latest) and writes it as map_server YAML + PGM.
absl::Status ExportMap(const CommandContext& context, const std::string& map_id,
                       uint32_t version, const std::string& yaml_path);
absl::Status DeleteMap(const CommandContext& context, const std::string& map_id);

/// Lists robots with their connection state and last pose.
absl::Status ListRobots(const CommandContext& context);
/// Streams WatchFleet and prints one line per robot update; stops after `max_updates`
/// messages (0 = never) or `duration_s` seconds (0 = never).
absl::Status WatchFleet(const CommandContext& context, double rate_hz, int max_updates,
                        double duration_s);

}  // namespace fleetnav::ctl
