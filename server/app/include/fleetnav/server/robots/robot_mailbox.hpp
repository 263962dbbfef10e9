#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fleetnav/core/job_assignment.hpp"
#include "fleetnav/core/robot_stop.hpp"

namespace fleetnav::server {

/// The way from the use cases to connected robots (implemented by the AgentService edge).
/// Sends never block; they return false when the robot has no open stream.
class RobotMailbox {
 public:
  virtual ~RobotMailbox() = default;
  virtual bool SendAssignment(const std::string& robot_id, const JobAssignment& assignment) = 0;
  /// A pause, resume or cancel (clearances go through SendClearance, with their waits).
  virtual bool SendCommand(const std::string& robot_id, const JobCommand& command) = 0;
  virtual bool SendClearance(const std::string& robot_id, const ClearanceNotice& clearance) = 0;
  /// Tells every connected robot that a map or its marker set has a new version.
  virtual void BroadcastMapUpdate(const std::string& map_id, uint32_t map_version,
                                  uint32_t marker_set_version) = 0;
  /// Tells every connected robot every operator's stop in force.
  virtual void BroadcastStops(const std::vector<RobotStop>& stops) { (void)stops; }
  /// Tells every connected robot a map's zones as put (`version` 0 and no zones: deleted).
  virtual void BroadcastZones(uint32_t version, const ZoneSet& zones) {
    (void)version;
    (void)zones;
  }
};

}  // namespace fleetnav::server
