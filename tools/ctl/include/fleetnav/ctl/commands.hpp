#pragma once

#include <grpcpp/channel.h>

#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace fleetnav::ctl {

/// What every fleetnavctl command needs: the server channel, the output stream, the format,
/// and the operator's bearer token (sent with every call when not empty).
struct CommandContext {
  std::shared_ptr<grpc::Channel> channel;
  std::ostream* out = nullptr;
  bool json = false;
  double timeout_s = 10.0;
  std::string token;
};

/// Uploads a ROS map_server map (YAML and the PGM it names) as a new version of `map_id`.
absl::Status ImportMap(const CommandContext& context, const std::string& map_id,
                       const std::string& yaml_path, const std::string& description);
/// Lists the latest version of every map.
absl::Status ListMaps(const CommandContext& context);
/// Downloads a map version (0 = latest) and writes it as map_server YAML + PGM.
absl::Status ExportMap(const CommandContext& context, const std::string& map_id, uint32_t version,
                       const std::string& yaml_path);
/// Draws a map version (0 = latest) with the site's latest marker set and the routes on the
/// map into a PNG (see RenderSiteMapPng); pixels_per_cell 0 picks a size.
absl::Status RenderMap(const CommandContext& context, const std::string& map_id, uint32_t version,
                       const std::string& png_path, int pixels_per_cell);
absl::Status DeleteMap(const CommandContext& context, const std::string& map_id);

/// Lists robots with their connection state and last pose.
absl::Status ListRobots(const CommandContext& context);
/// Removes an offline robot that holds no job from the server's registry and store.
absl::Status ForgetRobot(const CommandContext& context, const std::string& robot_id);
/// Makes an operator token of `role_name` (viewer, operator, admin) and prints its secret
/// (alone on stdout, or in the JSON object); the server keeps only its hash.
absl::Status CreateToken(const CommandContext& context, const std::string& name,
                         const std::string& role_name);
/// Lists the server's operator tokens (file and created), without secrets.
absl::Status ListTokens(const CommandContext& context);
/// Revokes a created token: the server refuses it from the next call on.
absl::Status RevokeToken(const CommandContext& context, const std::string& name);
/// Streams WatchFleet and prints one line per robot update; stops after `max_updates`
/// messages (0 = never) or `duration_s` seconds (0 = never).
absl::Status WatchFleet(const CommandContext& context, double rate_hz, int max_updates,
                        double duration_s);

}  // namespace fleetnav::ctl

namespace fleetnav::ctl {

/// Uploads a marker YAML file as a new version of its map's marker set (`--map` overrides the
/// file's `map:`).
absl::Status PutMarkers(const CommandContext& context, const std::string& map_id,
                        const std::string& yaml_path);
absl::Status GetMarkers(const CommandContext& context, const std::string& map_id, uint32_t version);
/// Deletes every version of a map's marker set (refused while routes or unfinished jobs use it).
absl::Status DeleteMarkers(const CommandContext& context, const std::string& map_id);
/// Uploads a zone YAML file (docs/file-formats.md) as a new version of its map's zones
/// (`--map` overrides the file's `map:`).
absl::Status PutZones(const CommandContext& context, const std::string& map_id,
                      const std::string& yaml_path);
/// Prints a map's zones (version 0 = latest) as zone YAML, or JSON.
absl::Status GetZones(const CommandContext& context, const std::string& map_id, uint32_t version);
/// Lists every map's latest zones with their counts by kind.
absl::Status ListZones(const CommandContext& context);
/// Deletes every version of a map's zones.
absl::Status DeleteZones(const CommandContext& context, const std::string& map_id);
/// What an operator's stop covers: the whole fleet, or a zone (of `map_id`, which may be empty
/// when the zone's name is on one map only).
struct StopTarget {
  bool whole_fleet = false;
  std::string map_id;
  std::string zone;
};
/// Stops the robots of the target (not a safety-rated emergency stop).
absl::Status StopRobots(const CommandContext& context, const StopTarget& target,
                        const std::string& reason);
/// Clears the target's stop.
absl::Status ResumeRobots(const CommandContext& context, const StopTarget& target);
/// Lists the stops in force.
absl::Status ListStops(const CommandContext& context);
/// Uploads a route YAML file as a new version of its route.
absl::Status PutRoute(const CommandContext& context, const std::string& yaml_path);
absl::Status GetRoute(const CommandContext& context, const std::string& name);
absl::Status ListRoutes(const CommandContext& context, const std::string& map_id);
/// Deletes every version of a route (refused while an unfinished job runs it).
absl::Status DeleteRoute(const CommandContext& context, const std::string& name);

struct SubmitOptions {
  std::string route_name;    ///< either a route …
  std::vector<double> goal;  ///< … or a goal x, y, yaw_deg on goal_map_id
  std::string goal_map_id;
  std::string robot_id;
  int priority = 0;
  std::string idempotency_key;
  bool requeue_on_robot_lost = false;
};
/// Submits and prints the job; returns its id.
absl::StatusOr<std::string> SubmitJob(const CommandContext& context, const SubmitOptions& options);
absl::Status GetJob(const CommandContext& context, const std::string& job_id);
absl::Status ListJobs(const CommandContext& context, const std::string& state,
                      const std::string& robot_id, uint32_t page_size);
absl::Status CancelJob(const CommandContext& context, const std::string& job_id,
                       const std::string& reason);
/// Pauses an assigned or running job (the robot stops where it is), or resumes a paused one.
absl::Status PauseJob(const CommandContext& context, const std::string& job_id,
                      const std::string& reason);
absl::Status ResumeJob(const CommandContext& context, const std::string& job_id);
/// Follows a job's events with a live progress bar until it ends; the status is an error when
/// the job failed or was cancelled (so scripts can rely on the exit code).
absl::Status WatchJob(const CommandContext& context, const std::string& job_id);

}  // namespace fleetnav::ctl
