#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"

namespace fleetnav {

/// Which controller drives the robot (Lely thesis §6.3's five modes, split into their reactive
/// and map-based halves, plus idle, docking, paused and fault).
enum class NavigationMode {
  kIdle,
  kTurn,
  kStraight,
  kFreeNavigation,
  kFenceReactive,
  kFenceMapBased,
  kStripeReactive,
  kStripeMapBased,
  kDocking,
  kPaused,
  kFault,
};

/// The mode's name in logs and recordings: "fence_map_based", "stripe_reactive", ...
std::string_view NavigationModeName(NavigationMode mode);

enum class ConnectionState { kOnline, kStale, kOffline };
/// "online", "stale" or "offline".
std::string_view ConnectionStateName(ConnectionState state);

/// Planar velocity in base_link.
struct Twist2 {
  double vx_mps = 0.0;
  double vy_mps = 0.0;
  double yaw_rate_radps = 0.0;
};

/// What a robot reports many times a second. stamp_ns is the robot's clock (sim time in a
/// simulated run). covariance is row-major 3×3 over (x, y, yaw).
struct Telemetry {
  int64_t stamp_ns = 0;
  uint64_t sequence = 0;
  Pose2 pose_in_map;
  std::array<double, 9> covariance{};
  Pose2 pose_in_odom;
  Twist2 velocity;
  NavigationMode mode = NavigationMode::kIdle;
  double localization_confidence = 0.0;
  bool localization_lost = false;
  double battery_fraction = 1.0;
  std::string job_id;
  int action_index = -1;
  double job_progress_fraction = 0.0;
  double action_progress_fraction = 0.0;  ///< of action action_index
  /// The outline (length × width) of the trolley on the robot's lift; nullopt: it carries none.
  std::optional<Eigen::Vector2d> carried_load_m;
};

/// Who a robot says it is when it connects.
struct RobotIdentity {
  std::string robot_id;
  RobotModel model;
  std::vector<std::string> capabilities;
  std::string software_version;
  /// The agent stands before a clearance's gate within an action, so traffic coordination may
  /// clear its actions segment by segment (AgentHello.segment_clearances).
  bool segment_clearances = false;
  /// The agent drives a free-navigation action through the path a clearance plans for it
  /// (AgentHello.planned_paths), so traffic coordination may route it around robots that stand.
  bool planned_paths = false;
};

/// What the fleet server knows about one robot at one moment (its registry entry, also sent
/// to operators as RobotState).
struct RobotRecord {
  RobotIdentity identity;
  ConnectionState connection = ConnectionState::kOffline;
  std::optional<Telemetry> last_telemetry;
  int64_t last_seen_ns = 0;      ///< server clock
  uint64_t telemetry_count = 0;  ///< messages accepted since the server started
  std::string current_job_id;
  std::string traffic_wait;  ///< why traffic coordination holds the robot; empty when not
  /// Server-clock seconds it stood still (mode idle) while traffic coordination held it, since
  /// the server started: each telemetry adds the time since the previous one when it shows
  /// the robot standing and traffic_wait is set.
  double traffic_held_s = 0.0;
  uint64_t revision = 0;  ///< grows on every change; lets watchers send only what changed
};

}  // namespace fleetnav
