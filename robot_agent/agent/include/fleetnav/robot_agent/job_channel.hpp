#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fleetnav/core/job.hpp"
#include "fleetnav/core/job_assignment.hpp"
#include "fleetnav/core/robot_stop.hpp"
#include "fleetnav/core/sensor_frame.hpp"

namespace fleetnav::agent {

/// A map's zones as the server last told them while the agent ran (ZoneUpdate).
struct ToldZones {
  uint32_t version = 0;  ///< 0: the map's zones were deleted
  ZoneSet zones;
};

/// The agent's side of job dispatch: assignments and commands in, job events out. The server
/// link implements it; tests use a fake. Only BeginTick and EndTick may block the control loop,
/// and only in a simulated run's lockstep, where the simulator waits for the server anyway.
class JobChannel {
 public:
  virtual ~JobChannel() = default;
  virtual std::optional<JobAssignment> TakeAssignment() = 0;
  virtual std::vector<JobCommand> TakeCommands() = 0;
  /// Reports an event of the current job; events are delivered in order and never dropped.
  virtual void ReportEvent(const JobEvent& event) = 0;
  /// The job the robot is executing, announced again on every reconnect ("" when idle).
  virtual void SetCurrentJob(const std::string& job_id) = 0;
  /// Called once per frame as it arrives. In a simulated run's lockstep it returns once the
  /// server has taken in the tick ended last (what the server sent for that tick is then what
  /// the Take* calls of this frame see), or at once while there is no server to wait for. By
  /// default there is nothing to wait for.
  virtual void BeginTick() {}
  /// Called once per frame, after everything of the frame's tick was reported and before the
  /// command goes to the actuators. In a simulated run's lockstep it tells the server the tick
  /// is complete; the server takes it in while the simulator steps, and the next BeginTick
  /// waits for that. Before a hold of the simulation (`frame.holds_after`) it returns only once
  /// the server has taken the tick in. By default there is nothing to tell.
  virtual void EndTick(const SensorFrame& frame) { (void)frame; }
  /// The operators' stops in force, as the server last told them (none by default).
  virtual std::vector<RobotStop> Stops() { return {}; }
  /// The zones of `map_id` as the server last told them since the agent started (nullopt:
  /// none told; none by default).
  virtual std::optional<ToldZones> Zones(const std::string& map_id) {
    (void)map_id;
    return std::nullopt;
  }
  /// Whether the server is heard now: a stream is live and the server has welcomed the robot
  /// on it. By default (no server) it is.
  virtual bool HearsServer() { return true; }
};

}  // namespace fleetnav::agent
