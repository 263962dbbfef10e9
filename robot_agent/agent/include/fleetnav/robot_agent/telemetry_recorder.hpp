#pragma once

#include <ostream>
#include <string>
#include <utility>

#include "fleetnav/robot_agent/telemetry_sink.hpp"

namespace fleetnav::agent {

/// A TelemetrySink that writes each message's estimated position as a CSV line
/// "robot_id,estimate,x,y,t_s,mode,action_index" (the trajectory format of fleetnav-sim
/// --render, which reads the first four fields; t_s the robot's clock: sim time in a simulated
/// run; mode as NavigationModeName) and passes the message on to the next sink. The stream
/// must outlive it. Not thread-safe.
class TelemetryRecorder : public TelemetrySink {
 public:
  TelemetryRecorder(std::string robot_id, std::ostream* out, TelemetrySink* next)
      : robot_id_(std::move(robot_id)), out_(out), next_(next) {}
  void Publish(const Telemetry& telemetry) override;

 private:
  std::string robot_id_;
  std::ostream* out_;
  TelemetrySink* next_;
};

}  // namespace fleetnav::agent
