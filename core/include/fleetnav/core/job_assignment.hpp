#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fleetnav/core/job.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/segment_gate.hpp"
#include "fleetnav/core/traffic_plan.hpp"

namespace fleetnav {

/// A job as a robot receives it, the same on both sides of the agent stream: the job, resolved
/// to fixed versions of its route, map (`job.map_id`) and marker set, and where the robot
/// begins. The route is shared (the server's site cache and traffic coordination hold the same
/// one), never copied. A value type.
struct JobAssignment {
  Job job;
  std::shared_ptr<const Route> route = std::make_shared<const Route>();
  uint32_t route_version = 0;
  uint32_t map_version = 0;         ///< 0: unknown, the agent uses what it has
  uint32_t marker_set_version = 0;  ///< 0: the map has no marker set
  uint32_t zone_set_version = 0;    ///< 0: the map has no zones
  /// The route's beginning, or — for a job the robot held before its agent restarted — the
  /// action it was in and how much of it was done.
  RoutePosition resume;
};

/// What the server tells a robot about its job besides the assignment. kClearance: traffic
/// coordination lets the robot start the job's actions up to `cleared_up_to_action` (-1 after
/// a reconnect: nothing beyond the action it is in until the server says again), and within
/// that action only up to `hold`'s gate when it is set (segment clearances).
enum class JobCommandType { kPause, kResume, kCancel, kClearance };

/// A path traffic coordination planned for one free-navigation action of the job, around the
/// robots that stand (docs/server.md, "Traffic coordination"): the robot drives through these
/// waypoints (map frame) to the action's goal instead of planning the leg on the map alone.
/// `id` names the plan, so a path told again is not taken twice.
struct ActionPath {
  int action_index = 0;
  uint64_t id = 0;
  std::vector<Eigen::Vector2d> waypoints_m;
  bool operator==(const ActionPath&) const = default;
};

struct JobCommand {
  JobCommandType type = JobCommandType::kCancel;
  std::string job_id;
  std::string reason;
  int cleared_up_to_action = -1;
  std::optional<SegmentHold> hold;  ///< kClearance: stand before this gate of that action
  std::vector<ActionPath> paths;    ///< kClearance: the cleared actions' planned paths
};

/// What the server tells a robot about its job's traffic: the actions it may enter, what holds
/// the next (each wait an edge: this robot's `to_action` waits for `from_robot_id` to finish
/// `from_action`, in the jobs' action numbers; -1: before its first), and why, in words.
struct ClearanceNotice {
  std::string job_id;
  int cleared_up_to_action = -1;
  std::vector<TrafficDependency> waits;
  std::string wait_reason;  ///< empty when nothing holds the robot
  /// Only part of cleared_up_to_action is cleared: the robot stands before this gate.
  std::optional<SegmentHold> hold;
  /// Paths planned for actions up to cleared_up_to_action (robots that said planned_paths).
  std::vector<ActionPath> paths;
};

}  // namespace fleetnav
