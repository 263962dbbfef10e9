#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_state.hpp"

// What the simulator knows that no robot does (its ground truth) and the faults it can be told
// to inject: value types shared by the simulator and the wire (proto/convert), with no engine.

namespace fleetnav {

/// Where a simulated robot truly is and how it moves, and how often it touched something.
struct RobotTruth {
  std::string robot_id;
  Pose2 pose;
  Twist2 velocity;
  double up_z = 1.0;
  /// Contact episodes since the start (or the last Reset): a run of consecutive ticks in which
  /// this robot touches the same thing counts once. The floor never counts.
  int collisions_world = 0;   ///< with walls, fences, boxes, poles
  int collisions_robots = 0;  ///< with other robots
  int collisions() const { return collisions_world + collisions_robots; }
};

/// One contact episode: a robot touched another robot or something static.
struct SimContact {
  std::string robot_id;
  std::string other;  ///< another robot's id, or "static"
  int64_t sim_time_ns = 0;
};

/// Where a trolley stands, and which robot carries it ("" when none).
struct TrolleyTruth {
  std::string trolley_id;
  Pose2 pose;
  std::string carrier_robot_id;
};

/// The whole simulation's ground truth at one tick.
struct GroundTruthSnapshot {
  uint64_t tick = 0;
  int64_t sim_time_ns = 0;
  std::vector<RobotTruth> robots;
  std::vector<TrolleyTruth> trolleys;
  std::vector<SimContact> contacts;
  /// Smallest distance between two robots' circumscribed circles so far (a lower bound on the
  /// footprint distance); +inf with fewer than two robots.
  double min_separation_m = 0.0;
};

/// What a fault does (SimService.InjectFault, or `faults:` in the world file).
enum class FaultType : uint8_t {
  kHideUltrasonicRegion,  ///< ultrasonic echoes from inside the region are lost
  kRemoveFenceSegment,    ///< the parts of fences inside the region are taken away
  kRemoveStripeSegment,   ///< the parts of floor stripes inside the region are taken away
  kWheelSlipRegion,       ///< inside the region ground travel = factor × wheel travel
  kSensorDropout,         ///< a robot's sensor (or all of them) reports nothing for a while
  kSlowDown,              ///< a robot's drive does factor × what it is commanded
};

/// One fault: an axis-aligned region for the region faults, robot and sensor for the others.
/// duration_s 0 means until the next Reset. Value type.
struct FaultSpec {
  FaultType type = FaultType::kHideUltrasonicRegion;
  std::string label;  ///< e.g. the thesis's "A", "B", "C"
  Eigen::Vector2d region_min_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d region_max_m = Eigen::Vector2d::Zero();
  std::string robot_id;
  std::string sensor_name;  ///< empty: every sensor of the robot
  double duration_s = 0.0;
  double factor = 1.0;
  /// Whether a point lies in the fault's region.
  bool InRegion(const Eigen::Vector2d& p) const {
    return p.x() >= region_min_m.x() && p.y() >= region_min_m.y() && p.x() <= region_max_m.x() &&
           p.y() <= region_max_m.y();
  }
  bool IsRegionFault() const {
    return type == FaultType::kHideUltrasonicRegion || type == FaultType::kRemoveFenceSegment ||
           type == FaultType::kRemoveStripeSegment || type == FaultType::kWheelSlipRegion;
  }
};

/// "hide_ultrasonic", "remove_fence", "remove_stripe", "wheel_slip", "sensor_dropout",
/// "slow_down".
std::string_view FaultTypeName(FaultType type);
absl::StatusOr<FaultType> FaultTypeByName(std::string_view name);

}  // namespace fleetnav
