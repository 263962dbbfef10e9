#pragma once

#include <string>
#include <string_view>

#include "absl/status/status.h"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/robot_agent/perception.hpp"

namespace fleetnav::agent {

struct SafetyParams {
  /// Stall: motion commanded (≥ these speeds) but none measured (≤ these) for stall_after_s.
  double stall_after_s = 2.0;
  double stall_command_mps = 0.03;
  double stall_command_radps = 0.05;
  double stall_measured_mps = 0.01;
  double stall_measured_radps = 0.01;
  /// Localization must report lost for this long before the robot is stopped.
  double lost_after_s = 0.5;
  /// A robot whose agent has not heard the server (no live stream with its welcome) for this
  /// long stands, its job held, until it hears it again: an operator's stop made meanwhile
  /// cannot reach it (docs/server.md, "Stops"). Robot time (the agent's ticks).
  double stop_after_link_loss_s = 1.0;
  absl::Status Validate() const;
};

enum class SafetyStop { kNone, kBumper, kStall, kLocalizationLost };

struct SafetyVerdict {
  SafetyStop stop = SafetyStop::kNone;
  std::string reason;
};

/// The top of the twist priority (the thesis's twist_mux, §6.6): decides each tick whether the
/// robot must stop whatever its navigation mode says — the bumper closed, the drive stalled
/// (commanded motion, none measured by the wheels for 2 s), or the localizer lost the robot.
/// Latches the first stop until Reset(). Not thread-safe.
class SafetyMonitor {
 public:
  explicit SafetyMonitor(SafetyParams params = {}) : params_(params) {}
  /// `commanded` is the twist sent on the previous tick; `measured` the odometry's twist;
  /// `lost_reason` says why the localizer counts itself lost (may be empty).
  const SafetyVerdict& Check(const Perception& perception, const Twist2& commanded,
                             const Twist2& measured, bool localization_lost, double dt_s,
                             std::string_view lost_reason = {});
  const SafetyVerdict& verdict() const { return verdict_; }
  void Reset();

 private:
  SafetyParams params_;
  SafetyVerdict verdict_;
  double stalled_s_ = 0.0;
  double lost_s_ = 0.0;
};

}  // namespace fleetnav::agent
