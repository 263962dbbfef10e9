#pragma once

#include <string>

#include "absl/status/status.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/robot_agent/control/common/line_memory.hpp"
#include "fleetnav/robot_agent/control/common/motion_controller.hpp"
#include "fleetnav/robot_agent/control/modes/motion_controllers.hpp"

namespace fleetnav::agent {

struct FenceFollowingParams {
  /// Yaw rate per metre of fence-distance error. The ultrasonic sits ahead of the axle, so a
  /// proportional law on its distance is a look-ahead controller: e'' + L·k·e' + v·k·e = 0,
  /// overdamped for the Lely (L = 1.57 m) at k = 0.6 and v ≤ 0.5 m/s.
  double gain_radps_per_m = 0.6;
  double max_yaw_rate_radps = 0.25;
  /// A reading further than this from the expected distance is a post, a cow or noise.
  double outlier_m = 0.5;
  /// A leg may start up to this far off its fence distance: the first echo within the first
  /// start_search_m of travel places the fence.
  double start_offset_m = 1.0;
  double start_search_m = 1.0;
  /// Ticks without a usable echo before map-based fallback, and ticks with echoes before the
  /// reactive law takes over again (hysteresis against single dropouts).
  int lost_after_ticks = 5;
  int found_after_ticks = 10;
  /// Travel over which fence points are kept for the fence line used in map-based fallback.
  double line_memory_m = 6.0;
  absl::Status Validate() const;
};

/// Fence navigation (Lely thesis §6.6.3, Fig. 6.14): drive along a feeding fence at a set
/// distance with a P law on the side ultrasonic's range (measured from the sensor). While the
/// echo is there, the fence points it measures are placed in the map with the localizer's pose
/// and a fence line is fitted to them; where the fence is missing (a gap, a region the
/// ultrasonic cannot see) the same law runs on the estimated pose's distance to that line
/// (map-based fallback), and the reactive law resumes once the fence answers again. Ends
/// after `distance_m` of travel. Not thread-safe.
class FenceFollowingController : public MotionController {
 public:
  FenceFollowingController(const FenceNavigationAction& action, const SensorMount& ultrasonic,
                           MotionProfile profile, FenceFollowingParams params = {});
  ControlOutput Step(const ControlInput& input) override;

 private:
  /// The distance of the sensor point from the fence line, towards the fence side.
  double DistanceToLine(const Pose2& sensor_in_map) const;

  FenceNavigationAction action_;
  SensorMount ultrasonic_;
  MotionProfile profile_;
  FenceFollowingParams params_;
  double side_sign_;  ///< +1 when the fence is on the left
  bool started_ = false;
  bool fence_placed_ = false;  ///< an echo placed the fence line at the leg's start
  Pose2 last_odom_;
  double travelled_m_ = 0.0;
  double last_speed_mps_ = 0.0;
  bool map_based_ = false;
  int missing_ticks_ = 0;
  int present_ticks_ = 0;
  LineMemory line_;
};

}  // namespace fleetnav::agent
