#pragma once

#include <Eigen/Core>

#include "fleetnav/core/pose2.hpp"

namespace fleetnav {

/// Where traffic coordination lets a robot go within an action: up to the end of segment
/// `segment` of action `action_index`. A segment ends at a gate: the line through the gate
/// pose's point, square to its heading (the direction of travel there, not the robot's yaw).
/// The robot stands before the gate until it is cleared further (docs/server.md, "Traffic
/// coordination"). A value type.
struct SegmentHold {
  int action_index = -1;
  int segment = 0;
  Pose2 gate;
};

/// How far `position_m` lies before the gate's line along the direction of travel (negative:
/// beyond it).
double DistanceBeforeGate(const Pose2& gate, const Eigen::Vector2d& position_m);

/// Whether a robot at `position_m` has reached the gate: within `reach_m` of its point and at
/// most `tolerance_m` before its line (a robot held at a gate stops just before it). The reach
/// keeps a path that bends back past the line far from the point from counting.
bool ReachedGate(const Pose2& gate, const Eigen::Vector2d& position_m, double tolerance_m = 0.2,
                 double reach_m = 1.0);

/// The fastest a robot at `position_m`, driving along `velocity_in_map_mps`, may go towards a
/// gate it is held at and still stop `stop_before_m` before its line, braking at `decel_mps2`.
/// Unlimited (a large number) while it is more than `approach_m` from the gate's point or does
/// not drive the gate's way (a path that bends back past the line elsewhere).
double SpeedLimitBeforeGate(const Pose2& gate, const Eigen::Vector2d& position_m,
                            const Eigen::Vector2d& velocity_in_map_mps, double decel_mps2,
                            double stop_before_m = 0.1, double approach_m = 2.5);

}  // namespace fleetnav
