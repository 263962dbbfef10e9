#pragma once

#include <optional>
#include <vector>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/planner/coordination/route_prediction.hpp"

namespace fleetnav::planner {

/// A piece of a predicted action that traffic coordination orders on its own, so that robots
/// follow one another through a shared place a segment apart instead of an action apart.
struct ActionSegment {
  std::vector<Pose2> poses;  ///< from where the segment before it ended to where it ends
  double duration_s = 0.0;
  /// Where it ends, as a gate: its last pose's point, with the yaw of the direction of travel
  /// there (core/segment_gate.hpp). Nullopt for the action's last segment, which ends with the
  /// action.
  std::optional<Pose2> gate;
  bool ends_at_stop = false;  ///< it ends where the way comes nearest one of the stops
};

/// Cuts `action` into segments of at least `segment_m` of travel each (a shorter rest joins
/// the last one); a turn in place, or `segment_m` <= 0, is one segment. A segment also ends
/// where the way comes nearest each of `stops` (in the order of travel; a robot stepping aside
/// stands there, at that segment's gate, until it is cleared on). The duration is shared out
/// by length.
std::vector<ActionSegment> SplitIntoSegments(const PredictedAction& action, double segment_m,
                                             const std::vector<Eigen::Vector2d>& stops = {});

}  // namespace fleetnav::planner
