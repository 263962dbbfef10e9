#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fleetnav/core/job.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/planner/coordination/traffic_schedule.hpp"

namespace fleetnav::server {

/// A job as a robot receives it: resolved to fixed versions of its route, map and marker set.
struct Assignment {
  Job job;
  /// Shared with the site cache and traffic coordination: a long route is never copied.
  std::shared_ptr<const Route> route = std::make_shared<const Route>();
  uint32_t route_version = 0;
  uint32_t map_version = 0;
  uint32_t marker_set_version = 0;  ///< 0: the map has no marker set
  /// Where the robot begins: the route's beginning, or where a restarted agent left off.
  RoutePosition resume;
};

/// Which actions of its job a robot may enter (traffic coordination) and what holds the next.
struct ClearanceNotice {
  std::string job_id;
  int cleared_up_to_action = -1;
  std::vector<planner::TrafficWait> waits;
  std::string wait_reason;  ///< empty when nothing holds the robot
};

enum class RobotCommandType { kPause, kResume, kCancel };

/// The way from the use cases to connected robots (implemented by the AgentService edge).
/// Sends never block; they return false when the robot has no open stream.
class RobotMailbox {
 public:
  virtual ~RobotMailbox() = default;
  virtual bool SendAssignment(const std::string& robot_id, const Assignment& assignment) = 0;
  virtual bool SendCommand(const std::string& robot_id, RobotCommandType type,
                           const std::string& job_id, const std::string& reason) = 0;
  virtual bool SendClearance(const std::string& robot_id, const ClearanceNotice& clearance) = 0;
  /// Tells every connected robot that a map or its marker set has a new version.
  virtual void BroadcastMapUpdate(const std::string& map_id, uint32_t map_version,
                                  uint32_t marker_set_version) = 0;
};

}  // namespace fleetnav::server
