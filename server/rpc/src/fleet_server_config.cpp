#include "fleetnav/server/rpc/fleet_server_config.hpp"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <set>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::server {
namespace {

absl::Status CheckKeys(const YAML::Node& node, const std::set<std::string>& known,
                       const std::string& where) {
  if (!node.IsMap()) return absl::InvalidArgumentError(absl::StrCat(where, ": expected a mapping"));
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    if (known.count(key) == 0) {
      return absl::InvalidArgumentError(absl::StrCat(where, ": unknown key '", key, "'"));
    }
  }
  return absl::OkStatus();
}

template <typename T>
absl::Status Read(const YAML::Node& node, const std::string& key, const std::string& where,
                  T* value) {
  if (!node[key]) return absl::OkStatus();
  try {
    *value = node[key].as<T>();
  } catch (const YAML::Exception&) {
    return absl::InvalidArgumentError(absl::StrCat(where, key, ": bad value"));
  }
  return absl::OkStatus();
}

absl::StatusOr<FleetServerConfig> ConfigFromYaml(const YAML::Node& root, FleetServerConfig config) {
  if (root.IsNull()) return config;
  RETURN_IF_ERROR(CheckKeys(root,
                            {"listen", "db", "db_wait_s", "log_level", "agent_threads", "insecure",
                             "tls", "limits", "timeouts", "charging"},
                            "config"));
  FleetServerParams& p = config.params;
  RETURN_IF_ERROR(Read(root, "listen", "", &p.listen_address));
  RETURN_IF_ERROR(Read(root, "db", "", &p.db_path));
  RETURN_IF_ERROR(Read(root, "db_wait_s", "", &p.postgres.connect_wait_s));
  RETURN_IF_ERROR(Read(root, "log_level", "", &config.log_level));
  RETURN_IF_ERROR(Read(root, "agent_threads", "", &p.agent_stream_threads));
  RETURN_IF_ERROR(Read(root, "insecure", "", &config.insecure));
  if (const YAML::Node tls = root["tls"]) {
    RETURN_IF_ERROR(CheckKeys(tls, {"cert", "key", "client_ca", "tokens"}, "tls"));
    RETURN_IF_ERROR(Read(tls, "cert", "tls.", &p.security.cert_path));
    RETURN_IF_ERROR(Read(tls, "key", "tls.", &p.security.key_path));
    RETURN_IF_ERROR(Read(tls, "client_ca", "tls.", &p.security.client_ca_path));
    RETURN_IF_ERROR(Read(tls, "tokens", "tls.", &p.security.tokens_path));
  }
  if (p.agent_stream_threads < 1 || p.agent_stream_threads > 64) {
    return absl::InvalidArgumentError(
        absl::StrCat("agent_threads: must be in [1, 64], got ", p.agent_stream_threads));
  }
  if (const YAML::Node limits = root["limits"]) {
    RETURN_IF_ERROR(CheckKeys(
        limits,
        {"max_message_bytes", "max_page_size", "max_map_cells", "max_markers", "max_zones",
         "max_zone_vertices", "max_route_actions", "max_waypoints_per_action", "max_capabilities",
         "max_footprint_points", "max_sensors", "max_text_bytes", "site_cache_mb"},
        "limits"));
    RETURN_IF_ERROR(Read(limits, "max_message_bytes", "limits.", &p.max_message_bytes));
    RETURN_IF_ERROR(Read(limits, "max_page_size", "limits.", &p.jobs.max_page_size));
    RETURN_IF_ERROR(Read(limits, "max_map_cells", "limits.", &p.limits.max_map_cells));
    RETURN_IF_ERROR(Read(limits, "max_markers", "limits.", &p.limits.max_markers));
    RETURN_IF_ERROR(Read(limits, "max_zones", "limits.", &p.limits.max_zones));
    RETURN_IF_ERROR(Read(limits, "max_zone_vertices", "limits.", &p.limits.max_zone_vertices));
    RETURN_IF_ERROR(Read(limits, "max_route_actions", "limits.", &p.limits.max_route_actions));
    RETURN_IF_ERROR(
        Read(limits, "max_waypoints_per_action", "limits.", &p.limits.max_waypoints_per_action));
    RETURN_IF_ERROR(Read(limits, "max_capabilities", "limits.", &p.limits.max_capabilities));
    RETURN_IF_ERROR(
        Read(limits, "max_footprint_points", "limits.", &p.limits.max_footprint_points));
    RETURN_IF_ERROR(Read(limits, "max_sensors", "limits.", &p.limits.max_sensors));
    RETURN_IF_ERROR(Read(limits, "max_text_bytes", "limits.", &p.limits.max_text_bytes));
    int64_t cache_mb = p.site_cache.budget_bytes >> 20;
    RETURN_IF_ERROR(Read(limits, "site_cache_mb", "limits.", &cache_mb));
    p.site_cache.budget_bytes = cache_mb << 20;
  }
  if (const YAML::Node timeouts = root["timeouts"]) {
    RETURN_IF_ERROR(CheckKeys(
        timeouts,
        {"stale_after_s", "lost_robot_timeout_s", "dispatch_period_s", "pose_history_period_s",
         "pose_history_retention_s", "evict_offline_robots_after_s"},
        "timeouts"));
    RETURN_IF_ERROR(Read(timeouts, "pose_history_period_s", "timeouts.", &p.pose_history.period_s));
    RETURN_IF_ERROR(
        Read(timeouts, "pose_history_retention_s", "timeouts.", &p.pose_history.retention_s));
    RETURN_IF_ERROR(Read(timeouts, "stale_after_s", "timeouts.", &p.registry.stale_after_s));
    RETURN_IF_ERROR(
        Read(timeouts, "lost_robot_timeout_s", "timeouts.", &p.jobs.lost_robot_timeout_s));
    RETURN_IF_ERROR(Read(timeouts, "dispatch_period_s", "timeouts.", &p.dispatch_period_s));
    RETURN_IF_ERROR(Read(timeouts, "evict_offline_robots_after_s", "timeouts.",
                         &p.jobs.evict_offline_robots_after_s));
  }
  if (const YAML::Node charging = root["charging"]) {
    RETURN_IF_ERROR(
        CheckKeys(charging, {"below_fraction", "charged_fraction", "routes"}, "charging"));
    RETURN_IF_ERROR(Read(charging, "below_fraction", "charging.", &p.jobs.charge_below_fraction));
    RETURN_IF_ERROR(Read(charging, "charged_fraction", "charging.", &p.jobs.charged_fraction));
    if (const YAML::Node routes = charging["routes"]) {
      if (!routes.IsMap()) {
        return absl::InvalidArgumentError("charging.routes: expected {map_id: route_name, ...}");
      }
      for (const auto& entry : routes) {
        p.jobs.charging_routes[entry.first.as<std::string>()] = entry.second.as<std::string>();
      }
    }
  }
  static const std::set<std::string> kLevels = {"trace", "debug", "info", "warn", "error"};
  if (kLevels.count(config.log_level) == 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "log_level: one of trace, debug, info, warn, error; got '", config.log_level, "'"));
  }
  RETURN_IF_ERROR(p.Validate());
  return config;
}

}  // namespace

absl::StatusOr<FleetServerConfig> ParseFleetServerConfig(std::string_view yaml_text,
                                                         FleetServerConfig config) {
  // yaml-cpp throws for text it cannot read and for a value of another shape than asked (a key
  // that is a list, a section that is a scalar): both are the file's fault.
  try {
    return ConfigFromYaml(YAML::Load(std::string(yaml_text)), std::move(config));
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat("config: ", e.what()));
  }
}

absl::StatusOr<FleetServerConfig> LoadFleetServerConfig(const std::string& path,
                                                        FleetServerConfig defaults) {
  std::ifstream in(path);
  if (!in) return absl::NotFoundError(absl::StrCat("cannot read config '", path, "'"));
  std::stringstream text;
  text << in.rdbuf();
  absl::StatusOr<FleetServerConfig> config = ParseFleetServerConfig(text.str(), defaults);
  if (!config.ok()) {
    return absl::Status(config.status().code(),
                        absl::StrCat(path, ": ", config.status().message()));
  }
  return config;
}

}  // namespace fleetnav::server
