#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "fleetnav/core/job.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/segment_gate.hpp"

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
  /// The route's beginning, or — for a job the robot held before its agent restarted — the
  /// action it was in and how much of it was done.
  RoutePosition resume;
};

/// What the server tells a robot about its job besides the assignment. kClearance: traffic
/// coordination lets the robot start the job's actions up to `cleared_up_to_action` (-1 after
/// a reconnect: nothing beyond the action it is in until the server says again), and within
/// that action only up to `hold`'s gate when it is set (segment clearances).
enum class JobCommandType { kPause, kResume, kCancel, kClearance };

struct JobCommand {
  JobCommandType type = JobCommandType::kCancel;
  std::string job_id;
  std::string reason;
  int cleared_up_to_action = -1;
  std::optional<SegmentHold> hold;  ///< kClearance: stand before this gate of that action
};

}  // namespace fleetnav
