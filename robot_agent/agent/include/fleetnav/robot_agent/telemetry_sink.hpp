#pragma once

#include "fleetnav/core/robot_state.hpp"

namespace fleetnav::agent {

/// Where the agent's telemetry goes (the server link, or a recorder in tests). Publish never
/// blocks the control loop: an implementation that cannot keep up drops the oldest messages.
class TelemetrySink {
 public:
  virtual ~TelemetrySink() = default;
  virtual void Publish(const Telemetry& telemetry) = 0;
};

}  // namespace fleetnav::agent
