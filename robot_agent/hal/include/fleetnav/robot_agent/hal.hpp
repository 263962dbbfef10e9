#pragma once

#include <optional>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/sensor_frame.hpp"

namespace fleetnav::agent {

/// The robot's hardware as the agent sees it: one sensor frame per control tick in, one
/// actuator command per tick out. Real drivers, the simulator over SimService, or an
/// in-process simulation implement it; the agent never knows which. NextFrame() blocks until
/// the next tick; it returns nullopt when the hardware (or simulation) has ended.
class RobotHal {
 public:
  virtual ~RobotHal() = default;
  virtual absl::StatusOr<std::optional<SensorFrame>> NextFrame() = 0;
  virtual absl::Status Send(const ActuatorCommand& command) = 0;
};

}  // namespace fleetnav::agent
