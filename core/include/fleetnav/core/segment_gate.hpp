#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

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

/// A robot counts as at a gate within this much of its point and its line (ReachedGate), and a
/// path that turns back before the line stands where it comes within kGateTurnReachM of the
/// point (PathDistanceToGate): the agent and fleetnavd must agree on both.
inline constexpr double kGateReachM = 1.0;
inline constexpr double kGateTurnReachM = 0.3;

/// How far `position_m` lies before the gate's line along the direction of travel (negative:
/// beyond it).
double DistanceBeforeGate(const Pose2& gate, const Eigen::Vector2d& position_m);

/// Whether a robot at `position_m` has reached the gate: within `reach_m` of its point and at
/// most `tolerance_m` before its line (a robot held at a gate stops just before it), or within
/// `turn_reach_m` of the point (where a path that turns back before the line stands,
/// PathDistanceToGate). The reach keeps a path that bends back past the line far from the
/// point from counting.
bool ReachedGate(const Pose2& gate, const Eigen::Vector2d& position_m, double tolerance_m = 0.2,
                 double reach_m = kGateReachM, double turn_reach_m = kGateTurnReachM);

/// The fastest a robot at `position_m`, driving along `velocity_in_map_mps`, may go towards a
/// gate it is held at and still stop `stop_before_m` before its line, braking at `decel_mps2`.
/// Unlimited (a large number) while it is more than `approach_m` from the gate's point or does
/// not drive the gate's way (a path that bends back past the line elsewhere).
double SpeedLimitBeforeGate(const Pose2& gate, const Eigen::Vector2d& position_m,
                            const Eigen::Vector2d& velocity_in_map_mps, double decel_mps2,
                            double stop_before_m = 0.1, double approach_m = 2.5);

/// How far a robot drives along its own path (`path_ahead`: poses in path order, the first
/// where it is now) before it stands `stop_before_m` short of the gate's line: to the first
/// place where the path crosses that line within `reach_m` of the gate's point. A path that
/// comes within `turn_reach_m` of the point and turns away before the line (a smoothed path that
/// turns back there) stands where it comes closest on that first approach. Nullopt when the path
/// does neither (the gate is behind the robot or off its way). Path order, unlike a test of the
/// robot's heading, holds a robot whose way turns back just before the gate.
std::optional<double> PathDistanceToGate(const Pose2& gate, std::span<const Pose2> path_ahead,
                                         double stop_before_m = 0.1, double reach_m = kGateReachM,
                                         double turn_reach_m = kGateTurnReachM);

}  // namespace fleetnav
